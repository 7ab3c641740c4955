// What an ED event calendar orders by: one absolute time per entry (disks 0..n−1, then
// the timer agents), read in place from the loop's per-entry event records at a fixed
// stride, so that scheduling an event writes one record and the calendar reads the same
// line. Calendars read keys, never write them.
#pragma once
#include <cstddef>

namespace grainflow::ed {

struct CalendarKeys {
  const double* base = nullptr;
  std::size_t stride = 1;  // in doubles
  double operator[](int e) const { return base[static_cast<std::size_t>(e) * stride]; }
  const double* at(int e) const { return base + static_cast<std::size_t>(e) * stride; }
};

}  // namespace grainflow::ed
