// The error a bad scene raises: every problem found in the file and the --set overrides,
// collected so the user fixes them in one go. Each names where (file:line:column or the
// --set), the key, the value and what is allowed (ARCHITECTURE.md, "Errors").
#pragma once
#include <string>
#include <vector>

#include "engine/core/error.hpp"

namespace grainflow::scenes {

struct SceneIssue {
  std::string location;  // "scenes/a.toml:12:9", "--set run.seed=x", or the file name
  std::string key;       // dotted path, "" for syntax errors
  std::string message;   // full sentence without the location
  std::string text() const { return location.empty() ? message : location + ": " + message; }
};

class SceneError : public grainflow::Error {
public:
  explicit SceneError(std::vector<SceneIssue> issues) : Error(compose(issues)), issues_(std::move(issues)) {}
  const std::vector<SceneIssue>& issues() const { return issues_; }

private:
  static std::string compose(const std::vector<SceneIssue>& issues) {
    std::string s = issues.size() == 1 ? std::string("invalid scene:\n")
                                       : std::to_string(issues.size()) + " problems in the scene:\n";
    // The first kShown problems (in file order); a file of a million unknown keys must not
    // print a million lines.
    constexpr std::size_t kShown = 20;
    for (std::size_t k = 0; k < issues.size() && k < kShown; ++k) s += "  " + issues[k].text() + "\n";
    if (issues.size() > kShown) s += "  … and " + std::to_string(issues.size() - kShown) + " more\n";
    if (!s.empty()) s.pop_back();
    return s;
  }
  std::vector<SceneIssue> issues_;
};

}  // namespace grainflow::scenes
