// The bucket calendar on its own (engine/ed/bucket_calendar.hpp), against a brute-force
// minimum: whatever the tuning, it must pop the entry of least (key, index) among the
// finite keys, through re-schedulings to the near and the far future, infinite keys,
// removals and window rebuilds, and through the duplicate copies lazy deletion leaves when
// an entry returns to a key it had or the calendar is told twice of one change. Small
// systems in the engine's tests leave the coarse tier (buckets of F fine buckets) nearly
// empty; a small F here exercises its spreading and its stale copies.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "engine/ed/bucket_calendar.hpp"
#include "engine/ed/system_state.hpp"

namespace ed = grainflow::ed;

namespace {

int brute_force_top(const std::vector<double>& key) {
  int best = -1;
  for (int e = 0; e < static_cast<int>(key.size()); ++e)
    if (std::isfinite(key[e]) && (best < 0 || key[e] < key[best])) best = e;  // ties: lower index
  return best;
}

struct Tuning {
  double per_bucket, span;
  int fine_per_coarse;
};

// Runs `pops` events on n entries: each pop re-schedules the popped entry and a few
// others (as a collision re-predicts its parties and an agent touches disks), now and
// then to never, to a tie, to "now", or far beyond the window.
void check(const Tuning& tn, int n, int pops, std::uint64_t seed, bool spreading_ahead = false) {
  std::mt19937_64 rng(seed);
  std::exponential_distribution<double> wait(1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> key(n);
  for (double& k : key) k = u(rng) < 0.05 ? ed::kNever : wait(rng);
  ed::BucketCalendar cal(tn.per_bucket, tn.span, tn.fine_per_coarse);
  if (spreading_ahead) cal = ed::BucketCalendar::spreading_ahead(tn.per_bucket, tn.span, tn.fine_per_coarse);
  cal.reset(ed::CalendarKeys{key.data(), 1}, nullptr, n - 2, 2);
  double now = 0.0;
  auto reschedule = [&](int e) {
    const double r = u(rng);
    if (r < 0.03) key[e] = ed::kNever;
    else if (r < 0.06) key[e] = now;                     // at once
    else if (r < 0.08) key[e] = now + 50.0 * wait(rng);  // far beyond the window
    else if (r < 0.10) {  // a tie with another entry's key
      const double other = key[static_cast<int>(rng() % n)];
      key[e] = other < ed::kNever ? other : now;
    }
    else if (r < 0.13) {  // away and back to the same key: copies of one key pile up
      const double back = key[e] < ed::kNever && key[e] >= now ? key[e] : now + wait(rng);
      key[e] = now + wait(rng);
      cal.update(e);
      key[e] = back;
      cal.update(e);
    }
    else key[e] = now + wait(rng);
    if (key[e] < now) key[e] = now;
    cal.update(e);
    if (u(rng) < 0.02) cal.update(e);  // told twice of one change
  };
  int popped = 0, spread = 0;
  for (int k = 0; k < pops; ++k) {
    const int e = cal.top();
    const int want = brute_force_top(key);
    ASSERT_EQ(e, want) << "pop " << k;
    if (e < 0) break;
    ASSERT_GE(key[e], now);
    now = key[e];
    ++popped;
    reschedule(e);
    for (int q = static_cast<int>(rng() % 3); q > 0; --q) reschedule(static_cast<int>(rng() % n));
    // A lane spreads the next coarse bucket ahead, a chunk at a time, while it waits.
    if (spreading_ahead)
      for (int q = static_cast<int>(rng() % 3); q > 0; --q) spread += cal.spread_ahead();
    if (u(rng) < 0.002) {  // a disk leaves
      const int gone = static_cast<int>(rng() % (n - 2));
      key[gone] = ed::kNever;
      cal.removed(gone, 0);
    }
  }
  EXPECT_GT(popped, pops / 2);
  if (spreading_ahead) {
    EXPECT_GT(spread, 0);  // some chunks were spread ahead, not all at their turn
  }
}

}  // namespace

TEST(BucketCalendar, PopsTheLeastKeyWithTheDefaultTuning) { check({2.0, 8.0, 512}, 3000, 60000, 1); }

TEST(BucketCalendar, PopsTheLeastKeyThroughSmallCoarseBuckets) {
  for (int f : {1, 2, 4, 16}) check({2.0, 8.0, f}, 2000, 40000, 10 + f);
}

TEST(BucketCalendar, PopsTheLeastKeySpreadingAhead) {
  // A lane's calendar: the next coarse bucket spread ahead a chunk at a time now and then,
  // the rest when it comes up (crowded buckets hold more chunks than there are fine buckets).
  check({2.0, 8.0, 512}, 3000, 60000, 21, true);
  for (int f : {1, 2, 4, 16}) check({2.0, 8.0, f}, 2000, 40000, 30 + f, true);
  check({0.5, 1.0, 4}, 1500, 30000, 23, true);
  check({40.0, 2.0, 8}, 1500, 30000, 24, true);
}

TEST(BucketCalendar, RefusesCoarseBucketsOfOtherThanPowersOfTwo) {
  EXPECT_THROW(ed::BucketCalendar(2.0, 8.0, 5), grainflow::Error);
  EXPECT_THROW(ed::BucketCalendar(2.0, 8.0, 0), grainflow::Error);
  EXPECT_NO_THROW(ed::BucketCalendar(2.0, 8.0, 1));
}

TEST(BucketCalendar, PopsTheLeastKeyWithNarrowAndCrowdedWindows) {
  check({0.5, 1.0, 4}, 1500, 30000, 3);   // short window: most events in the overflow
  check({40.0, 2.0, 8}, 1500, 30000, 4);  // crowded buckets: large heaps, many stale copies
}

TEST(BucketCalendar, EmptiesAndRefills) {
  // Every key infinite, then all back: top() must say "nothing" and then recover.
  const int n = 200;
  std::vector<double> key(n, ed::kNever);
  ed::BucketCalendar cal(2.0, 8.0, 4);
  cal.reset(ed::CalendarKeys{key.data(), 1}, nullptr, n, 0);
  EXPECT_EQ(cal.top(), -1);
  for (int e = 0; e < n; ++e) {
    key[e] = 1.0 + 0.01 * ((e * 37) % n);
    cal.update(e);
  }
  double last = 0.0;
  for (int k = 0; k < n; ++k) {
    const int e = cal.top();
    ASSERT_EQ(e, brute_force_top(key));
    ASSERT_GE(key[e], last);
    last = key[e];
    key[e] = ed::kNever;
    cal.update(e);
  }
  EXPECT_EQ(cal.top(), -1);
}
