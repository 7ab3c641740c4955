// Line-by-line text input for the particle-file readers: tracks the line number so that
// every error names file:line, and parses whole tokens as numbers (no silent partial
// parses such as "1.5abc" -> 1.5).
//
// Input is bounded so that no file can make a reader allocate or read without limit: a
// line is at most kMaxLineBytes long, a NUL byte ends reading (binary data, /dev/zero),
// and counts read from a file are checked by check_particle_limit() / plausible_particles()
// before memory is sized by them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/error.hpp"

namespace grainflow::io {

// The longest line accepted (1 MiB). Real lines are far shorter: a particle line of a
// thousand 25-character columns is 25 KiB, an extended-XYZ comment line a few KiB. The
// limit bounds the memory one line can take and lets a file without line breaks fail
// after reading about 1 MiB instead of all of it.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;
// The most particles one frame may claim (10^9). ParticleFrame keeps at least 44 bytes per
// particle (id, position, radius, type), so a billion particles is already 44 GB, beyond
// what `grainflow render` can draw; larger counts are corrupt or hostile headers.
inline constexpr std::int64_t kMaxParticles = 1'000'000'000;

// The file ends inside a frame: it is still being written (a running LAMMPS job's dump) or
// was cut short. Every frame read before this one was complete, so a caller may keep them
// and say what was left out; anyone else treats it as the error it is.
class TruncatedFrame : public Error {
public:
  using Error::Error;
};

class LineReader {
public:
  // Throws grainflow::Error when the path cannot be opened or is not something text can be
  // read from: a directory, a block device or a socket. Regular files, pipes (FIFOs,
  // process substitution, /dev/stdin) and character devices are read.
  explicit LineReader(std::string path);
  LineReader(LineReader&& other) noexcept;
  LineReader& operator=(LineReader&&) = delete;
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;
  ~LineReader();

  // Next line without its end-of-line ("\n" or "\r\n"); false at end of file.
  // The view stays valid until the next call. Throws when the line is longer than
  // kMaxLineBytes, holds a NUL byte, or reading fails.
  bool next(std::string_view& line);
  // Up to `n` (at most kMaxLineBytes) bytes ahead of the next line, not consumed: lets the
  // format probe look at raw bytes (gzip magic) before they are checked as text.
  std::string_view peek(std::size_t n);
  // Back to the first line, so that the format probe and the reader share one open file
  // (a pipe cannot be opened twice). Throws if a pipe has already been read past what the
  // buffer still holds.
  void rewind();
  // Line number of the line last returned by next() (1-based; 0 before the first).
  long line_number() const { return line_; }
  // The line last returned is the file's last and has no '\n': a file another program is
  // still writing (or one cut short) ends this way, perhaps in the middle of a number.
  bool last_line_unterminated() const { return unterminated_; }
  const std::string& path() const { return path_; }
  // Bytes after the line last returned, when the file's size is known (a regular file
  // not shorter than what was read); nullopt for pipes, devices and /proc-like files.
  // `refresh` re-reads the size, for a file another program is still writing.
  std::optional<std::uint64_t> bytes_left(bool refresh = false);

  // Throws grainflow::Error("path:line: message") for the current line / a given line.
  [[noreturn]] void fail(std::string_view message) const { fail_at(line_, message); }
  [[noreturn]] void fail_at(long line, std::string_view message) const;
  // The same message as fail(), thrown as TruncatedFrame: the file ended inside a frame.
  [[noreturn]] void fail_truncated(std::string_view message) const;

private:
  // Reads more input after the buffered bytes, first moving the unread bytes to the front
  // when the buffer has little room left. False at end of file.
  bool fill();

  std::string path_;
  int fd_ = -1;
  bool regular_ = false;          // a regular file: its size bounds what is left to read
  std::uint64_t size_ = 0;        // st_size when regular_ (as of the last fstat)
  std::unique_ptr<char[]> buf_;   // kBufferBytes, allocated once per reader
  std::size_t pos_ = 0;           // start of the next line in buf_
  std::size_t end_ = 0;           // end of the buffered bytes
  std::size_t nul_;               // index of the first NUL byte in buf_[.. end_), or npos
  std::uint64_t origin_ = 0;      // file offset of buf_[0]
  bool eof_ = false;
  bool unterminated_ = false;
  long line_ = 0;
};

// Throws "path:line: the header claims N particles, more than the limit of 10^9" for the
// current line when a count read from it exceeds kMaxParticles (or is negative).
void check_particle_limit(const LineReader& in, std::int64_t n);
// How many particles a frame claiming `n` on line `count_line`, whose particle lines have
// `columns` columns, should be sized for before its lines are read: at most what the rest
// of the file can hold (each particle line takes at least 2 * columns bytes) when its size
// is known, a modest first reservation for streams. Memory beyond that must grow with the
// lines actually read. Throws "path:count_line: the header claims N particles but the
// file holds at most M (B bytes left ...)" when the rest of the file cannot even hold N
// lines; smaller shortfalls are found by reading (truncated frame, short line).
std::size_t plausible_particles(LineReader& in, std::int64_t n, long count_line, int columns);

// Splits on blanks (space, tab, \r); the views point into `line`.
void split_ws(std::string_view line, std::vector<std::string_view>& out);
std::string_view trim(std::string_view s);
// Whole-token parses; a leading '+' is accepted. Return false on any other text.
bool parse_double(std::string_view token, double& out);
bool parse_int64(std::string_view token, std::int64_t& out);
// Text from a file made safe for an error message: bytes outside printable ASCII are
// written as \xNN (no control sequences reach the terminal) and text longer than
// `max_chars` is cut, ending in "...".
std::string printable(std::string_view text, std::size_t max_chars = 40);
// A token shortened to at most 40 characters, quoted, for error messages (printable()).
std::string quote_token(std::string_view token);

// One frame read by `read` (a reader's own frame parser): an error on a last line without
// its '\n' — a line still being written (`1 1 0.52 0.3` of a longer one, `ITEM: BOX BOU`) —
// means the file ends inside this frame, and becomes TruncatedFrame.
template <class Read>
bool read_frame_or_truncated(const LineReader& in, Read&& read) {
  try {
    return read();
  } catch (const TruncatedFrame&) {
    throw;
  } catch (const Error& e) {
    if (in.last_line_unterminated()) throw TruncatedFrame(std::string(e.what()) + " (the file's last line is unfinished)");
    throw;
  }
}

}  // namespace grainflow::io
