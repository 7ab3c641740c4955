#include "engine/io/line_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>

#include "engine/core/error.hpp"

namespace grainflow::io {
namespace {

// Twice the longest line: after the unread part of a line (at most kMaxLineBytes) is moved
// to the front, a read can still add at least 1 MiB.
constexpr std::size_t kBufferBytes = 2 * kMaxLineBytes;
// Below this much free room the unread bytes are moved to the front before reading, so
// reads stay large (a read of a few bytes per call would be slow).
constexpr std::size_t kMinRead = std::size_t{64} << 10;
constexpr std::size_t npos = std::string_view::npos;

std::string type_error(const std::string& path, mode_t mode) {
  const char* what = S_ISDIR(mode) ? "a directory" : S_ISBLK(mode) ? "a block device" : S_ISSOCK(mode) ? "a socket" : nullptr;
  if (!what) return {};
  return "'" + path + "' is " + what + ", not a particle file";
}

}  // namespace

LineReader::LineReader(std::string path)
    : path_(std::move(path)), buf_(new char[kBufferBytes]), nul_(npos) {  // before open: no fd to leak
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    // A socket cannot be opened (ENXIO); say what it is rather than "No such device".
    struct stat st;
    if (::stat(path_.c_str(), &st) == 0)
      if (auto msg = type_error(path_, st.st_mode); !msg.empty()) throw Error(msg);
    throw Error(path_ + ": cannot open for reading (" + std::strerror(err) + ")");
  }
  struct stat st;
  if (::fstat(fd_, &st) != 0) {
    const int err = errno;
    ::close(fd_);
    throw Error(path_ + ": cannot read its file status (" + std::strerror(err) + ")");
  }
  // A directory opens but every read fails (EISDIR); a disk is no particle file either.
  if (auto msg = type_error(path_, st.st_mode); !msg.empty()) {
    ::close(fd_);
    throw Error(msg);
  }
  regular_ = S_ISREG(st.st_mode);
  size_ = regular_ ? static_cast<std::uint64_t>(st.st_size) : 0;
}

LineReader::LineReader(LineReader&& o) noexcept
    : path_(std::move(o.path_)),
      fd_(o.fd_),
      regular_(o.regular_),
      size_(o.size_),
      buf_(std::move(o.buf_)),
      pos_(o.pos_),
      end_(o.end_),
      nul_(o.nul_),
      origin_(o.origin_),
      eof_(o.eof_),
      unterminated_(o.unterminated_),
      line_(o.line_) {
  o.fd_ = -1;
}

LineReader::~LineReader() {
  if (fd_ >= 0) ::close(fd_);
}

// Called only while the unread bytes are at most kMaxLineBytes (next() and peek() check
// first), so after the move there is always room to read into.
bool LineReader::fill() {
  if (eof_) return false;
  if (pos_ > 0 && kBufferBytes - end_ < kMinRead) {
    std::memmove(buf_.get(), buf_.get() + pos_, end_ - pos_);
    if (nul_ != npos) nul_ -= pos_;
    origin_ += pos_;
    end_ -= pos_;
    pos_ = 0;
  }
  ssize_t got;
  do got = ::read(fd_, buf_.get() + end_, kBufferBytes - end_);
  while (got < 0 && errno == EINTR);
  if (got < 0) {
    const int err = errno;
    fail(std::string("read error after this line (") + std::strerror(err) + ")");
  }
  if (got == 0) return !(eof_ = true);
  // One memchr per read, not per line: text never holds NUL, so this finds binary data
  // (and /dev/zero) at the cost of a fast scan of what was read.
  if (nul_ == npos)
    if (const void* z = std::memchr(buf_.get() + end_, '\0', static_cast<std::size_t>(got)))
      nul_ = static_cast<std::size_t>(static_cast<const char*>(z) - buf_.get());
  end_ += static_cast<std::size_t>(got);
  return true;
}

bool LineReader::next(std::string_view& line) {
  // Offsets from pos_, which fill() may move: bytes [pos_, pos_ + seen) hold no '\n'.
  std::size_t seen = 0, len = 0;
  for (;;) {
    const char* start = buf_.get() + pos_;
    const char* nl = static_cast<const char*>(std::memchr(start + seen, '\n', end_ - pos_ - seen));
    len = nl ? static_cast<std::size_t>(nl - start) : end_ - pos_;
    if (nul_ != npos && nul_ < pos_ + len)
      fail_at(line_ + 1, "binary data (a NUL byte at byte " + std::to_string(nul_ - pos_ + 1) +
                             " of the line): not a text particle file");
    // Checked before reading on, so a file without line breaks stops after about 1 MiB.
    if (len > kMaxLineBytes)
      fail_at(line_ + 1, "line longer than 1 MiB (" + std::to_string(kMaxLineBytes) +
                             " bytes): not a text particle file, or a damaged one");
    if (nl) break;
    seen = len;
    if (!fill()) {
      if (pos_ == end_) return false;
      break;  // a last line without '\n'
    }
  }
  unterminated_ = pos_ + len >= end_ && eof_;
  line = std::string_view(buf_.get() + pos_, len);
  pos_ = std::min(pos_ + len + 1, end_);
  ++line_;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return true;
}

std::string_view LineReader::peek(std::size_t n) {
  n = std::min(n, kMaxLineBytes);
  while (end_ - pos_ < n && fill()) {
  }
  return std::string_view(buf_.get() + pos_, std::min(n, end_ - pos_));
}

void LineReader::rewind() {
  line_ = 0;
  unterminated_ = false;
  if (origin_ == 0) {  // the buffer still holds the start of the file
    pos_ = 0;
    return;
  }
  if (!regular_ || ::lseek(fd_, 0, SEEK_SET) != 0)
    throw Error(path_ + ": cannot re-read the start of this stream (more than " +
                std::to_string(kBufferBytes >> 20) + " MiB before its first non-blank line)");
  pos_ = end_ = 0;
  origin_ = 0;
  nul_ = npos;
  eof_ = false;
}

std::optional<std::uint64_t> LineReader::bytes_left(bool refresh) {
  if (!regular_) return std::nullopt;
  const std::uint64_t consumed = origin_ + pos_;
  if (refresh || consumed > size_) {
    struct stat st;
    if (::fstat(fd_, &st) != 0) return std::nullopt;
    size_ = static_cast<std::uint64_t>(st.st_size);
  }
  // More read than the size says: a /proc-like file (size 0) or one cut shorter meanwhile.
  if (consumed > size_) return std::nullopt;
  return size_ - consumed;
}

void LineReader::fail_at(long line, std::string_view message) const {
  throw Error(path_ + ":" + std::to_string(line) + ": " + std::string(message));
}

void LineReader::fail_truncated(std::string_view message) const {
  throw TruncatedFrame(path_ + ":" + std::to_string(line_) + ": " + std::string(message));
}

void check_particle_limit(const LineReader& in, std::int64_t n) {
  if (n < 0 || n > kMaxParticles)
    in.fail("the header claims " + std::to_string(n) + " particles, more than the limit of " +
            std::to_string(kMaxParticles) + " particles per frame");
}

std::size_t plausible_particles(LineReader& in, std::int64_t n, long count_line, int columns) {
  // A stream of unknown size gets this many particles up front (a few MB) and grows as
  // lines arrive.
  constexpr std::int64_t kStreamFirst = std::int64_t{1} << 16;
  // Even a plausible claim is not sized beyond this up front (about 1 GB of frame): a huge
  // sparse or zero-filled file could otherwise back a claim that no line will fill.
  constexpr std::int64_t kFirstCap = std::int64_t{1} << 24;
  const auto claim = static_cast<std::uint64_t>(n);
  // B bytes hold at most (B + 1) / 2 lines of any kind (a character and a '\n', the last
  // '\n' optional), and at most (B + 1) / (2 * columns) particle lines: every column is at
  // least a character followed by a blank or the end of the line.
  const auto lines = [](std::uint64_t left) { return (left + 1) / 2; };
  std::optional<std::uint64_t> left = in.bytes_left();
  // A file still being written (a running simulation) may have grown since it was opened.
  if (left && claim > lines(*left)) left = in.bytes_left(true);
  if (!left) return static_cast<std::size_t>(std::min(n, kStreamFirst));
  const std::uint64_t per_line = 2 * static_cast<std::uint64_t>(std::max(columns, 1));
  const std::uint64_t most = (*left + 1) / per_line;
  // Only a claim the file cannot meet even with one-character lines fails here. A smaller
  // shortfall is left to the reader, whose message is then more useful: a truncated frame
  // (a run killed while writing it) is reported where the file ends with the number of
  // lines read, a short line with its columns.
  if (claim > lines(*left))
    in.fail_at(count_line, "the header claims " + std::to_string(n) + " particles but the file holds at most " +
                               std::to_string(most) + " (" + std::to_string(*left) + " bytes left after line " +
                               std::to_string(in.line_number()) + "; a particle line of " + std::to_string(columns) +
                               " columns takes at least " + std::to_string(per_line) + " bytes)");
  return static_cast<std::size_t>(std::min({claim, most, static_cast<std::uint64_t>(kFirstCap)}));
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

std::string printable(std::string_view text, std::size_t max_chars) {
  static constexpr char kHex[] = "0123456789abcdef";
  const auto width = [](unsigned char c) -> std::size_t { return c >= 0x20 && c < 0x7f ? 1 : 4; };
  std::size_t total = 0;
  for (unsigned char c : text) total += width(c);
  const std::size_t room = total <= max_chars ? total : (max_chars > 3 ? max_chars - 3 : 0);
  std::string s;
  s.reserve(std::min(total, max_chars));
  for (unsigned char c : text) {
    if (s.size() + width(c) > room) break;
    if (width(c) == 1) {
      s.push_back(static_cast<char>(c));
    } else {
      s.append("\\x");
      s.push_back(kHex[c >> 4]);
      s.push_back(kHex[c & 15]);
    }
  }
  if (total > max_chars) s.append("...");
  return s;
}

std::string quote_token(std::string_view token) {
  // Appending (not "'" + std::string(...)) avoids a GCC 12 -Wrestrict false positive.
  std::string s(1, '\'');
  s.append(printable(token, 40));
  s.push_back('\'');
  return s;
}

}  // namespace grainflow::io
