// Line-by-line text input for the particle-file readers: tracks the line number so that
// every error names file:line, and parses whole tokens as numbers (no silent partial
// parses such as "1.5abc" -> 1.5).
#pragma once
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace grainflow::io {

class LineReader {
public:
  // Throws grainflow::Error when the file cannot be opened.
  explicit LineReader(std::string path);

  // Next line without its end-of-line ("\n" or "\r\n"); false at end of file.
  // The view stays valid until the next call.
  bool next(std::string_view& line);
  // Line number of the line last returned by next() (1-based; 0 before the first).
  long line_number() const { return line_; }
  const std::string& path() const { return path_; }

  // Throws grainflow::Error("path:line: message") for the current line / a given line.
  [[noreturn]] void fail(std::string_view message) const { fail_at(line_, message); }
  [[noreturn]] void fail_at(long line, std::string_view message) const;

private:
  std::string path_;
  std::ifstream in_;
  std::string buf_;
  long line_ = 0;
};

// Splits on blanks (space, tab, \r); the views point into `line`.
void split_ws(std::string_view line, std::vector<std::string_view>& out);
std::string_view trim(std::string_view s);
// Whole-token parses; a leading '+' is accepted. Return false on any other text.
bool parse_double(std::string_view token, double& out);
bool parse_int64(std::string_view token, std::int64_t& out);
// A token shortened to at most 40 characters, quoted, for error messages.
std::string quote_token(std::string_view token);

}  // namespace grainflow::io
