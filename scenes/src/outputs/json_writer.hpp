// A tiny streaming JSON writer for run.json (no dependency): objects, arrays, strings with
// correct escaping, integers, shortest round-trip doubles (non-finite written as null).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace grainflow::scenes {

// "…" with \" \\ \b \f \n \r \t and \u00XX for other control characters; UTF-8 passes as is.
std::string json_string(std::string_view s);
// Shortest text that parses back to `v`; "null" for NaN and infinities (JSON has none).
std::string json_number(double v);

// Usage: JsonWriter w; w.begin_object(); w.key("seed").value(1); w.end_object(); w.str().
// Indented two spaces per level. Misuse (a value where a key is needed) is a logic_error.
class JsonWriter {
public:
  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  JsonWriter& key(std::string_view k);
  JsonWriter& value(std::string_view s);
  JsonWriter& value(const char* s) { return value(std::string_view(s)); }
  JsonWriter& value(const std::string& s) { return value(std::string_view(s)); }
  JsonWriter& value(double v);
  JsonWriter& value(std::int64_t v);
  JsonWriter& value(int v) { return value(std::int64_t(v)); }
  JsonWriter& value(std::uint64_t v);
  JsonWriter& value(bool b);
  JsonWriter& null();

  // The document; complete only when every object/array is closed.
  const std::string& str() const { return out_; }
  bool complete() const { return stack_.empty() && !out_.empty(); }

private:
  void before_value();
  void raw(std::string_view text);
  struct Level {
    bool object;
    bool empty = true;
    bool key_pending = false;
  };
  std::vector<Level> stack_;
  std::string out_;
};

}  // namespace grainflow::scenes
