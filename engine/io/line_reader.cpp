#include "engine/io/line_reader.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>

#include "engine/core/error.hpp"

namespace grainflow::io {

LineReader::LineReader(std::string path) : path_(std::move(path)), in_(path_, std::ios::binary) {
  if (!in_) throw Error(path_ + ": cannot open for reading (" + std::strerror(errno) + ")");
}

bool LineReader::next(std::string_view& line) {
  if (!std::getline(in_, buf_)) {
    if (in_.bad()) fail("read error after this line");
    return false;
  }
  ++line_;
  if (!buf_.empty() && buf_.back() == '\r') buf_.pop_back();
  line = buf_;
  return true;
}

void LineReader::fail_at(long line, std::string_view message) const {
  throw Error(path_ + ":" + std::to_string(line) + ": " + std::string(message));
}

void split_ws(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
  while (i < n) {
    while (i < n && blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < n && !blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\v\f");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\v\f");
  return s.substr(first, last - first + 1);
}

bool parse_double(std::string_view t, double& out) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), out);
  return ec == std::errc() && ptr == t.data() + t.size();
}

bool parse_int64(std::string_view t, std::int64_t& out) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), out);
  return ec == std::errc() && ptr == t.data() + t.size();
}

std::string quote_token(std::string_view token) {
  // Appending (not "'" + std::string(...)) avoids a GCC 12 -Wrestrict false positive.
  std::string s(1, '\'');
  if (token.size() > 40) s.append(token.substr(0, 37)).append("...");
  else s.append(token);
  s.push_back('\'');
  return s;
}

}  // namespace grainflow::io
