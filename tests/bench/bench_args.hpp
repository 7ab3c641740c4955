// What the benchmarks take from their command lines, distrusted like any input: a number
// is the whole argument within its range, or the benchmark stops with its usage (exit 2)
// — std::atoi/atof would read "abc" as 0 and "2x" as 2 and run a meaningless size — and a
// scratch folder is one the benchmark made, never a folder of the user's that it would
// empty.
#pragma once
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "engine/io/line_reader.hpp"

namespace grainflow::bench {

// Prints "<prog>: <what>" and the usage to stderr, and exits with status 2.
[[noreturn]] inline void usage_error(const char* prog, const char* usage, const std::string& what) {
  std::fprintf(stderr, "%s: %s\nusage: %s\n", prog, what.c_str(), usage);
  std::exit(2);
}

// Stops with the usage when more than `n` arguments follow the program's name.
inline void at_most(const char* prog, const char* usage, int argc, char** argv, int n) {
  if (argc > n + 1) usage_error(prog, usage, std::string("unexpected argument ") + argv[n + 1]);
}

// How an error names argument `value` of `name` (absent: missing).
inline std::string shown(const std::string& name, const char* value) {
  return name + (value ? " '" + std::string(value) + "'" : std::string(" (missing)"));
}

// Argument `value` of `name` as a number in [lo, hi] (a whole number when `whole`).
inline double number_arg(const char* prog, const char* usage, const std::string& name, const char* value, double lo,
                         double hi, bool whole = false) {
  double v = 0.0;
  if (value == nullptr || !io::parse_double(value, v) || !(v >= lo && v <= hi) || (whole && v != std::floor(v))) {
    char range[96];
    std::snprintf(range, sizeof range, "%s from %.10g to %.10g", whole ? "a whole number" : "a number", lo, hi);
    usage_error(prog, usage, shown(name, value) + ": allowed " + range);
  }
  return v;
}

// Argument `value` of `name` as a list of whole numbers in [lo, hi], separated by `sep`
// ("1,2" or "10x10x20"), with exactly `count` of them when count > 0.
inline std::vector<int> whole_list(const char* prog, const char* usage, const std::string& name, const char* value,
                                   char sep, double lo, double hi, int count = 0) {
  std::vector<int> out;
  if (value != nullptr) {
    const std::string list = value;
    for (std::size_t b = 0;;) {
      const std::size_t e = std::min(list.find(sep, b), list.size());
      out.push_back(static_cast<int>(number_arg(prog, usage, name, list.substr(b, e - b).c_str(), lo, hi, true)));
      if (e == list.size()) break;
      b = e + 1;
    }
  }
  if (value == nullptr || (count > 0 && static_cast<int>(out.size()) != count))
    usage_error(prog, usage, shown(name, value) + ": allowed " +
                                 (count > 0 ? std::to_string(count) + " " : std::string()) +
                                 "whole numbers separated by '" + std::string(1, sep) + "'");
  return out;
}

// A scratch folder for a benchmark's files, emptied when it is made and removed at the end.
// It must not exist, or be one a benchmark made (it holds the marker file): a folder of the
// user's named by mistake is refused, and nothing in it is touched.
class ScratchDir {
public:
  ScratchDir(const char* prog, std::filesystem::path dir) : dir_(std::move(dir)) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(dir_, ec) && !fs::exists(dir_ / kMarker, ec)) {
      std::fprintf(stderr, "%s: scratch folder %s exists and was not made by a benchmark; name a new folder\n", prog,
                   dir_.c_str());
      std::exit(2);
    }
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / kMarker) << "scratch folder of a grainflow benchmark: removed when it ends\n";
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return dir_; }

private:
  static constexpr const char* kMarker = ".grainflow-bench-scratch";
  std::filesystem::path dir_;
};

}  // namespace grainflow::bench
