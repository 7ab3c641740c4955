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

void StatsCsv::check_columns(const std::vector<std::string>& columns) {
  std::set<std::string> seen;
  for (const auto& c : columns) {
    if (c.empty() || c == "time" || c.find_first_of(",\"\n\r") != std::string::npos || !seen.insert(c).second)
      throw Error("stats.csv column '" + c + "' is not allowed; allowed: unique non-empty names other than "
                  "'time' without commas, quotes or newlines");
  }
}

namespace {
std::chrono::steady_clock::duration seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
}
}  // namespace

StatsCsv::StatsCsv(std::filesystem::path final_path, std::vector<std::string> columns, double flush_interval_s)
    : columns_((check_columns(columns), std::move(columns))),
      file_(io::PartialFile::create(std::move(final_path))),
      flush_interval_(seconds(flush_interval_s)) {
  std::string header = "time";
  for (const auto& c : columns_) header += "," + c;
  header += "\n";
  file_.write(header);
  file_.flush();
  last_flush_ = std::chrono::steady_clock::now();
}

StatsCsv::StatsCsv(std::filesystem::path final_path, std::vector<std::string> columns, Position at,
                   double flush_interval_s)
    : columns_((check_columns(columns), std::move(columns))),
      file_(io::PartialFile::resume(std::move(final_path), at.bytes)),
      rows_(at.rows),
      flush_interval_(seconds(flush_interval_s)),
      last_flush_(std::chrono::steady_clock::now()) {}

void StatsCsv::row(double time, std::span<const double> values) {
  if (file_.finished()) throw std::logic_error("StatsCsv::row after finish()");
  if (values.size() != columns_.size())
    throw std::logic_error("StatsCsv::row: " + std::to_string(values.size()) + " values for " +
                           std::to_string(columns_.size()) + " columns");
  line_ = csv_number(time);
  for (double v : values) {
    line_ += ',';  // appended separately: `"," + std::string` trips a GCC 12 -Wrestrict false positive
    line_ += csv_number(v);
  }
  line_ += '\n';
  file_.write(line_);
  ++rows_;
  // Rows are samples, not events, so one clock read per row costs nothing.
  const auto now = std::chrono::steady_clock::now();
  if (now - last_flush_ >= flush_interval_) {
    file_.flush();
    last_flush_ = now;
  }
}

void StatsCsv::flush() {
  file_.flush();
  last_flush_ = std::chrono::steady_clock::now();
}

StatsCsv::Position StatsCsv::position() {
  flush();
  return {file_.size(), rows_};
}

void StatsCsv::finish() { file_.finish(); }

}  // namespace grainflow::scenes
