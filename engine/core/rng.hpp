// The one seeded random generator of a run (xoshiro256**, seeded through splitmix64),
// with our own uniform/normal transforms so that results are identical across standard
// libraries (std::normal_distribution is not specified bit-for-bit).
#pragma once
#include <cstdint>
#include <array>

namespace grainflow::core {

// Seed of a run's k-th independent random stream (obstacle walls, inlets, filters each
// draw from their own, so adding one never shifts another's numbers): the run's seed
// spread by the golden-ratio increment, offset by k. Rng's splitmix64 seeding decorrelates
// neighbouring seeds.
constexpr std::uint64_t substream_seed(std::uint64_t run_seed, std::uint64_t k) {
  return run_seed * 0x9e3779b97f4a7c15ULL + k;
}

class Rng {
public:
  explicit Rng(std::uint64_t seed = 1);

  std::uint64_t next_u64();
  // Uniform in [0, 1) with 53 random bits.
  double uniform();
  // Uniform in (0, 1]: safe as the argument of log().
  double uniform_pos() { return 1.0 - uniform(); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Unbiased integer in [0, n) (Lemire's multiply-and-reject); n > 0.
  std::uint64_t below(std::uint64_t n);
  // Standard normal (Marsaglia polar method; the second value is kept for the next call).
  double normal();
  double normal(double mean, double sd) { return mean + sd * normal(); }

  // Full state, for checkpoints: restoring it continues the same stream.
  struct State {
    std::array<std::uint64_t, 4> s;
    bool has_spare;
    double spare;
  };
  State state() const { return {s_, has_spare_, spare_}; }
  void set_state(const State& st) { s_ = st.s; has_spare_ = st.has_spare; spare_ = st.spare; }

private:
  std::array<std::uint64_t, 4> s_{};
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace grainflow::core
