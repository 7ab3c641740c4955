// Time until two freely moving hard disks touch (seed 003 §2.1, Eq. 2.3–2.5).
// Receding pairs (b = r·v ≥ 0) and misses (negative discriminant) are rejected before
// any square root; the root is taken in the cancellation-free form c / (−b + √D).
#pragma once
#include <cmath>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace grainflow::ed {

inline constexpr double kNever = std::numeric_limits<double>::infinity();

// dx, dy: r_ij = r_i − r_j; dvx, dvy: v_ij = v_i − v_j, both at the same instant.
// sigma = (d_i + d_j)/2. Returns the delay until contact (≥ 0) or kNever.
// Eq. 2.5's smaller root (−b − √D)/v² equals c/(−b + √D) with c = r² − σ²; the latter
// does not subtract nearly equal numbers when the pair is far apart.
inline double pair_collision_time(double dx, double dy, double dvx, double dvy, double sigma) {
  const double b = dx * dvx + dy * dvy;
  if (b >= 0.0) return kNever;  // moving apart (or sliding past at constant distance)
  const double v2 = dvx * dvx + dvy * dvy;
  const double c = dx * dx + dy * dy - sigma * sigma;
  const double disc = b * b - v2 * c;
  if (disc < 0.0) return kNever;  // grazing miss
  // An approaching pair already in contact (round-off puts it a hair inside) collides now.
  if (c <= 0.0) return 0.0;
  return c / (-b + std::sqrt(disc));
}

// IEEE square root without the errno check std::sqrt carries (NaN for x < 0), so that a
// caller masking invalid lanes stays free of branches and library calls.
inline double sqrt_unchecked(double x) {
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_sqrt_pd(_mm_set_sd(x)));
#else
  return std::sqrt(x);
#endif
}

// Same value as pair_collision_time, bit for bit, computed without data-dependent branches:
// in a neighbourhood scan whether a pair approaches is a coin flip, and the mispredicted
// branches cost more than one division and one square root per pair (and they squash the
// neighbours' loads already in flight).
inline double pair_collision_time_branchless(double dx, double dy, double dvx, double dvy, double sigma) {
  const double b = dx * dvx + dy * dvy;
  const double v2 = dvx * dvx + dvy * dvy;
  const double c = dx * dx + dy * dy - sigma * sigma;
  const double disc = b * b - v2 * c;
  const double root = c / (-b + sqrt_unchecked(disc));
  const double t = c <= 0.0 ? 0.0 : root;
  return (b < 0.0) & (disc >= 0.0) ? t : kNever;
}

}  // namespace grainflow::ed
