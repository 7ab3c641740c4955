#include "scenes/src/outputs/json_writer.hpp"

#include "scenes/src/scene/toml_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace grainflow::scenes {

// JSON and TOML basic strings escape alike: one escaper for both (scene/toml_text).
std::string json_string(std::string_view s) { return toml_string(s); }

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

void JsonWriter::before_value() {
  if (stack_.empty()) {
    if (!out_.empty()) throw std::logic_error("JsonWriter: second top-level value");
    return;
  }
  Level& l = stack_.back();
  if (l.object) {
    if (!l.key_pending) throw std::logic_error("JsonWriter: value in an object without a key");
    l.key_pending = false;
    return;
  }
  out_ += l.empty ? "\n" : ",\n";
  out_.append(2 * stack_.size(), ' ');
  l.empty = false;
}

void JsonWriter::raw(std::string_view text) {
  before_value();
  out_ += text;
}

JsonWriter& JsonWriter::begin_object() {
  before_value();
  out_ += '{';
  stack_.push_back({true});
  return *this;
}

JsonWriter& JsonWriter::begin_array() {
  before_value();
  out_ += '[';
  stack_.push_back({false});
  return *this;
}

JsonWriter& JsonWriter::end_object() {
  if (stack_.empty() || !stack_.back().object || stack_.back().key_pending)
    throw std::logic_error("JsonWriter: end_object without a matching begin_object");
  const bool empty = stack_.back().empty;
  stack_.pop_back();
  if (!empty) {
    out_ += '\n';
    out_.append(2 * stack_.size(), ' ');
  }
  out_ += '}';
  return *this;
}

JsonWriter& JsonWriter::end_array() {
  if (stack_.empty() || stack_.back().object) throw std::logic_error("JsonWriter: end_array without begin_array");
  const bool empty = stack_.back().empty;
  stack_.pop_back();
  if (!empty) {
    out_ += '\n';
    out_.append(2 * stack_.size(), ' ');
  }
  out_ += ']';
  return *this;
}

JsonWriter& JsonWriter::key(std::string_view k) {
  if (stack_.empty() || !stack_.back().object || stack_.back().key_pending)
    throw std::logic_error("JsonWriter: key outside an object");
  Level& l = stack_.back();
  out_ += l.empty ? "\n" : ",\n";
  out_.append(2 * stack_.size(), ' ');
  out_ += json_string(k) + ": ";
  l.empty = false;
  l.key_pending = true;
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view s) {
  raw(json_string(s));
  return *this;
}
JsonWriter& JsonWriter::value(double v) {
  raw(json_number(v));
  return *this;
}
JsonWriter& JsonWriter::value(std::int64_t v) {
  raw(std::to_string(v));
  return *this;
}
JsonWriter& JsonWriter::value(std::uint64_t v) {
  raw(std::to_string(v));
  return *this;
}
JsonWriter& JsonWriter::value(bool b) {
  raw(b ? "true" : "false");
  return *this;
}
JsonWriter& JsonWriter::null() {
  raw("null");
  return *this;
}

}  // namespace grainflow::scenes
