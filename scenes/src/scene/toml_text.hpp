// TOML text of single values: shortest round-trip numbers and escaped basic strings.
// Used by the effective-scene writer, error messages and the schema reference, so a value
// printed anywhere reads back to the same bits.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace grainflow::scenes {

// Shortest decimal text that parses back to exactly `v`; always has a '.' or an exponent
// so TOML reads it as a float ("1.0", "2.5e-07"); "inf"/"nan" spelled the TOML way.
std::string toml_float(double v);
std::string toml_int(std::int64_t v);
// "…" with \" \\ \b \t \n \f \r and \u00xx for other control characters (DEL included);
// UTF-8 passes as is. The same text is a valid JSON string: run.json uses it too.
std::string toml_string(std::string_view s);

}  // namespace grainflow::scenes
