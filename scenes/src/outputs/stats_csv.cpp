#include "scenes/src/outputs/stats_csv.hpp"

#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>

#include "engine/core/error.hpp"

namespace grainflow::scenes {

std::string csv_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

StatsCsv::StatsCsv(std::filesystem::path final_path, std::vector<std::string> columns, double flush_interval_s)
    : final_(std::move(final_path)), columns_(std::move(columns)) {
  partial_ = final_;
  partial_ += ".partial";
  std::set<std::string> seen;
  for (const auto& c : columns_) {
    if (c.empty() || c == "time" || c.find_first_of(",\"\n\r") != std::string::npos || !seen.insert(c).second)
      throw Error("stats.csv column '" + c + "' is not allowed; allowed: unique non-empty names other than "
                  "'time' without commas, quotes or newlines");
  }
  flush_interval_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(flush_interval_s));
  file_ = std::fopen(partial_.c_str(), "w");
  if (!file_) throw Error("cannot create '" + partial_.string() + "': " + std::strerror(errno));
  std::string header = "time";
  for (const auto& c : columns_) header += "," + c;
  header += "\n";
  check_write(std::fputs(header.c_str(), file_) >= 0);
  check_write(std::fflush(file_) == 0);
  last_flush_ = std::chrono::steady_clock::now();
}

StatsCsv::~StatsCsv() {
  if (file_) std::fclose(file_);
}

void StatsCsv::check_write(bool ok) {
  if (!ok) throw Error("cannot write '" + partial_.string() + "': " + std::strerror(errno));
}

void StatsCsv::row(double time, std::span<const double> values) {
  if (finished_) throw std::logic_error("StatsCsv::row after finish()");
  if (values.size() != columns_.size())
    throw std::logic_error("StatsCsv::row: " + std::to_string(values.size()) + " values for " +
                           std::to_string(columns_.size()) + " columns");
  line_ = csv_number(time);
  for (double v : values) {
    line_ += ',';  // appended separately: `"," + std::string` trips a GCC 12 -Wrestrict false positive
    line_ += csv_number(v);
  }
  line_ += '\n';
  check_write(std::fwrite(line_.data(), 1, line_.size(), file_) == line_.size());
  ++rows_;
  // Rows are samples, not events, so one clock read per row costs nothing.
  const auto now = std::chrono::steady_clock::now();
  if (now - last_flush_ >= flush_interval_) {
    check_write(std::fflush(file_) == 0);
    last_flush_ = now;
  }
}

void StatsCsv::flush() {
  if (file_) check_write(std::fflush(file_) == 0);
  last_flush_ = std::chrono::steady_clock::now();
}

void StatsCsv::finish() {
  if (finished_) return;
  flush();
  const int rc = std::fclose(file_);
  file_ = nullptr;
  check_write(rc == 0);
  std::error_code ec;
  std::filesystem::rename(partial_, final_, ec);
  if (ec) throw Error("cannot rename '" + partial_.string() + "' to '" + final_.string() + "': " + ec.message());
  finished_ = true;
}

}  // namespace grainflow::scenes
