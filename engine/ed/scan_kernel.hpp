// The arithmetic of a neighbourhood scan (EventLoop::evaluate) four candidates at a time in
// AVX2 lanes, for CPUs that have it (chosen at run time; on others the SSE2 two-lane loop
// and the scalar one do it). Every lane does the IEEE
// operations of pair_collision_time_branchless in the same order, with no fused
// multiply-add (AVX2 alone has none), and the minimum is taken in candidate order: the
// same bits as the two-lane loop on every CPU.
#pragma once
#include "engine/ed/pair_collision_time.hpp"
#include "engine/ed/system_state.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define GRAINFLOW_ED_AVX2 1
#endif

namespace grainflow::ed {

// A disk a scan considers: its id, and its cell's place in the scanned list of cells
// (the image shift is shx[k], shy[k]).
struct ScanCandidate {
  int j;
  int k;
};
// A list of n candidates is followed by kScanPad more, each the scanning disk itself
// (j = i, any k): its relative velocity to itself is zero, so it never gives an event,
// and the four-lane loop needs no tail.
inline constexpr int kScanPad = 3;

// What a scan is asked: disk i at di now (radius ri), the records at the common epoch
// `since` ago, the uniform radius ur (or mixed radii read from body), the cells' image
// shifts (read only when `shifted`, else zero: away from a periodic edge they are unset).
struct ScanQuery {
  const Disk* disk;
  const DiskBody* body;
  const double* shx;
  const double* shy;
  Disk di;
  double ri, ur, since;
  bool mixed, shifted;
};

#if defined(GRAINFLOW_ED_AVX2)
// Whether scans take the four-lane loop: where the CPU has AVX2. A test may set it false
// to run the two-lane loop on such a CPU (the results must not change).
inline bool& scan_uses_avx2() {
  static bool use = __builtin_cpu_supports("avx2");
  return use;
}

// Candidates cand[0 .. n) and their padding (kScanPad) in groups of four; `best`, `who`
// take any earlier pair event, as the two-lane loop would (candidate order, strict <).
[[gnu::target("avx2")]] inline void earliest_pair_avx2(const ScanQuery& q, const ScanCandidate* __restrict cand, int n,
                                                      double& best_out, int& who_out) {
  double best = best_out;
  int who = who_out;
  const Disk* __restrict disk = q.disk;
  const __m256d dt = _mm256_set1_pd(q.since), zero = _mm256_setzero_pd(), never = _mm256_set1_pd(kNever);
  const __m256d sign = _mm256_set1_pd(-0.0);
  const __m256d vlimit = _mm256_set1_pd(2.0 * (1.0 + 1e-12));
  const __m256d ix = _mm256_set1_pd(q.di.x), iy = _mm256_set1_pd(q.di.y), ivx = _mm256_set1_pd(q.di.vx),
                ivy = _mm256_set1_pd(q.di.vy), ir = _mm256_set1_pd(q.ri), usigma = _mm256_set1_pd(q.ri + q.ur);
  for (int k = 0; k < n; k += 4) {
    const ScanCandidate c0 = cand[k], c1 = cand[k + 1], c2 = cand[k + 2], c3 = cand[k + 3];
    // Four 32-byte records (x, y, vx, vy) transposed into x, y, vx, vy across the lanes.
    const __m256d r0 = _mm256_load_pd(&disk[c0.j].x), r1 = _mm256_load_pd(&disk[c1.j].x);
    const __m256d r2 = _mm256_load_pd(&disk[c2.j].x), r3 = _mm256_load_pd(&disk[c3.j].x);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);  // x0 x1 vx0 vx1, y0 y1 vy0 vy1
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    const __m256d x = _mm256_permute2f128_pd(t0, t2, 0x20), vx = _mm256_permute2f128_pd(t0, t2, 0x31);
    const __m256d y = _mm256_permute2f128_pd(t1, t3, 0x20), vy = _mm256_permute2f128_pd(t1, t3, 0x31);
    __m256d jx = _mm256_add_pd(x, _mm256_mul_pd(vx, dt));
    __m256d jy = _mm256_add_pd(y, _mm256_mul_pd(vy, dt));
    if (q.shifted) {  // (adding +0 instead changes no time)
      jx = _mm256_add_pd(jx, _mm256_set_pd(q.shx[c3.k], q.shx[c2.k], q.shx[c1.k], q.shx[c0.k]));
      jy = _mm256_add_pd(jy, _mm256_set_pd(q.shy[c3.k], q.shy[c2.k], q.shy[c1.k], q.shy[c0.k]));
    }
    const __m256d dx = _mm256_sub_pd(ix, jx), dy = _mm256_sub_pd(iy, jy);
    const __m256d dvx = _mm256_sub_pd(ivx, vx), dvy = _mm256_sub_pd(ivy, vy);
    const __m256d sigma =
        q.mixed ? _mm256_add_pd(ir, _mm256_set_pd(q.body[c3.j].r, q.body[c2.j].r, q.body[c1.j].r, q.body[c0.j].r))
                : usigma;
    const __m256d b = _mm256_add_pd(_mm256_mul_pd(dx, dvx), _mm256_mul_pd(dy, dvy));
    const __m256d v2 = _mm256_add_pd(_mm256_mul_pd(dvx, dvx), _mm256_mul_pd(dvy, dvy));
    const __m256d c =
        _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(sigma, sigma));
    const __m256d disc = _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(v2, c));
    const __m256d ok = _mm256_and_pd(_mm256_cmp_pd(b, zero, _CMP_LT_OQ), _mm256_cmp_pd(disc, zero, _CMP_GE_OQ));
    // No lane can beat `best` (see EventLoop::evaluate): skip the division and the root.
    const __m256d reach = _mm256_mul_pd(_mm256_mul_pd(_mm256_andnot_pd(sign, b), vlimit), _mm256_set1_pd(best));
    if (_mm256_movemask_pd(_mm256_and_pd(ok, _mm256_cmp_pd(c, reach, _CMP_LT_OQ))) == 0) continue;
    const __m256d root = _mm256_div_pd(c, _mm256_add_pd(_mm256_xor_pd(b, sign), _mm256_sqrt_pd(disc)));
    const __m256d t = _mm256_andnot_pd(_mm256_cmp_pd(c, zero, _CMP_LE_OQ), root);  // contact now: +0
    const __m256d tv = _mm256_or_pd(_mm256_and_pd(ok, t), _mm256_andnot_pd(ok, never));
    if (_mm256_movemask_pd(_mm256_cmp_pd(tv, _mm256_set1_pd(best), _CMP_LT_OQ)) == 0) continue;
    alignas(32) double tt[4];
    _mm256_store_pd(tt, tv);
    const int js[4] = {c0.j, c1.j, c2.j, c3.j};
    for (int l = 0; l < 4; ++l)
      if (tt[l] < best) {
        best = tt[l];
        who = js[l];
      }
  }
  best_out = best;
  who_out = who;
}
#endif

}  // namespace grainflow::ed
