// "Did you mean …?" for unknown keys, sections and enum values: the closest candidate by
// edit distance (optimal string alignment, case-insensitive), if close enough to be a typo.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace grainflow::scenes {

// Levenshtein distance counting an adjacent transposition as one edit, ignoring ASCII case.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The best candidate within max(1, (|word|+1)/3) edits; std::nullopt when none is that close.
std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace grainflow::scenes
