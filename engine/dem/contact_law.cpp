#include "engine/dem/contact_law.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "engine/dem/simd_clones.hpp"

namespace grainflow::dem {

namespace {

// Approach speed and tangential surface velocity from the normal, the relative velocity
// v_i − v_partner and W = R_i ω_i + R_j ω_j.
inline void relative_motion(ContactKinematics& k, const double vr[3], const double W[3]) {
  k.vn = vr[0] * k.n[0] + vr[1] * k.n[1] + vr[2] * k.n[2];
  k.vt[0] = vr[0] - k.vn * k.n[0] + (W[1] * k.n[2] - W[2] * k.n[1]);
  k.vt[1] = vr[1] - k.vn * k.n[1] + (W[2] * k.n[0] - W[0] * k.n[2]);
  k.vt[2] = vr[2] - k.vn * k.n[2] + (W[0] * k.n[1] - W[1] * k.n[0]);
}

// Two doubles in one SSE register (GCC/Clang vector extension).
using Pair = double __attribute__((vector_size(16)));
inline Pair load_pair(const double* p) {
  Pair v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The one generic contact loop; sub-models are inlined through the template parameters.
template <class N, class T, class C>
class ComposedLaw final : public ContactLaw {
public:
  static constexpr int kH = N::kHistory + T::kHistory + C::kHistory;
  static constexpr bool kNeedsMass = N::kNeedsMass || T::kNeedsMass;
  struct Params {
    typename N::Params n;
    typename T::Params t;
    typename C::Params c;
    bool operator==(const Params&) const = default;
  };

  ComposedLaw(const std::array<ContactParams, 9>& per, const std::array<double, 9>& meff) {
    for (int k = 0; k < 9; ++k) {
      params_[k] = {N::make(per[k], meff[k]), T::make(per[k], meff[k]), C::make(per[k], meff[k])};
      range_ = std::max(range_, C::range(params_[k].c));
    }
    uniform_ = true;
    for (int k : {type_pair(0, 1), type_pair(1, 0), type_pair(1, 1)})
      uniform_ = uniform_ && params_[k] == params_[0];
    uniform_wall_ = params_[type_pair(1, kWallType)] == params_[type_pair(0, kWallType)];
  }
  int history_size() const override { return kH; }
  double cohesion_range() const override { return range_; }

  bool evaluate(int tp, const ContactKinematics& k, double* h, bool update, ContactForce& out) const override {
    return eval(params_[tp], k, h, update, out);
  }
  double cohesion_force(int tp, const ContactKinematics& k) const override { return C::force(params_[tp].c, k); }

  // Branch-free, so that the contacts of a chunk run in SIMD lanes: the sub-models work
  // on a copy of the history, kept (update) only while the contact lasts.
  [[gnu::always_inline]] static bool eval(const Params& q, const ContactKinematics& k, double* h, bool update,
                                          ContactForce& out) {
    const bool touch = k.delta > 0.0;
    double hn[kH > 0 ? kH : 1];
    for (int a = 0; a < kH; ++a) hn[a] = h[a];
    double ft[3];
    double fn = N::force(q.n, k, hn, update);
    T::force(q.t, k, fn, hn + N::kHistory, update, ft);
    fn = touch ? fn : 0.0;
    for (int a = 0; a < 3; ++a) ft[a] = touch ? ft[a] : 0.0;
    if (update)
      for (int a = 0; a < kH; ++a) h[a] = touch ? hn[a] : 0.0;  // contact over: forget its history
    const double fc = C::force(q.c, k);
    const double fnet = fn - fc;  // repulsive along −n on particle i
    for (int a = 0; a < 3; ++a) out.f[a] = -fnet * k.n[a] + ft[a];
    out.c[0] = k.n[1] * ft[2] - k.n[2] * ft[1];
    out.c[1] = k.n[2] * ft[0] - k.n[0] * ft[2];
    out.c[2] = k.n[0] * ft[1] - k.n[1] * ft[0];
    return touch | (fc != 0.0);
  }

  // A block of up to kBlock contacts as a structure of arrays (field f of entry e at
  // base[f·kBlock + e]): independent contacts then run in SIMD lanes over contiguous
  // memory; the fixed stride keeps every field at a constant offset (no register per
  // field) and the block in L1. Outputs overwrite inputs that are no longer needed.
  struct Lanes {
    static constexpr std::size_t kBlock = 128;
    enum : std::size_t {
      kDx, kDy, kDz, kRi, kRj,
      kVr, kW = kVr + 3,            // v_i − v_j; R_i ω_i + R_j ω_j
      kMi = kW + 3, kMj, kType,
      kState, kHist,                // state: kOn + kTouch; history in and out
      kFields = kHist + kH,
      kF = kVr, kC = kW             // out: force on i, n × F_t
    };
    static constexpr double kOn = 1.0, kTouch = 2.0;  // force on; touching (history kept)
    double* base;
    std::size_t n;  // entries in use
    double* operator[](std::size_t f) const { return base + f * kBlock; }
  };
  // The calling thread's block (one per thread: chunks run in parallel).
  static Lanes lane_block(std::size_t n) {
    thread_local std::vector<double> buf(Lanes::kFields * Lanes::kBlock);
    return {buf.data(), n};
  }

  // One contact of the lanes, branch-free. Its locals live in this function (inlined into
  // the SIMD loop, where the compiler keeps them in vector registers). Wall lanes hold the
  // wall's unit normal (exact) in kDx..kDz and the centre's distance to the wall in kRj.
  template <bool kWall, bool kUniform, bool kUpdate>
  [[gnu::always_inline]] inline void evaluate_lane(const Lanes& L, std::size_t e, const Params& uniform_params,
                                                   double dt) const {
    const double dx = L[Lanes::kDx][e], dy = L[Lanes::kDy][e], dz = L[Lanes::kDz][e];
    const double ri = L[Lanes::kRi][e], rj = L[Lanes::kRj][e];
    const double mi = L[Lanes::kMi][e];
    ContactKinematics k;
    if constexpr (kWall) {
      k.n[0] = dx;
      k.n[1] = dy;
      k.n[2] = dz;
      k.delta = ri - rj;
      k.m_eff = mi;
      k.r_eff = ri;
    } else {
      const double rsq = dx * dx + dy * dy + dz * dz;
      const double rsum = ri + rj;
      const double r = std::sqrt(rsq), rinv = 1.0 / r;
      k.n[0] = dx * rinv;
      k.n[1] = dy * rinv;
      k.n[2] = dz * rinv;
      k.delta = rsum - r;
      // Reduced mass and radius cost a division each: only for sub-models that read them.
      const double mj = L[Lanes::kMj][e];
      k.m_eff = kNeedsMass ? mi * mj / (mi + mj) : 0.0;
      k.r_eff = C::kNeedsRadius ? ri * rj / rsum : 0.0;
    }
    const double vr[3] = {L[Lanes::kVr][e], L[Lanes::kVr + 1][e], L[Lanes::kVr + 2][e]};
    const double W[3] = {L[Lanes::kW][e], L[Lanes::kW + 1][e], L[Lanes::kW + 2][e]};
    relative_motion(k, vr, W);
    k.dt = dt;
    k.wall = kWall;
    double h[kH > 0 ? kH : 1];
    for (int c = 0; c < kH; ++c) h[c] = L[Lanes::kHist + c][e];
    const Params& prm = kUniform ? uniform_params : params_[static_cast<int>(L[Lanes::kType][e])];
    ContactForce out;
    const bool on = eval(prm, k, h, kUpdate, out);
    for (int c = 0; c < 3; ++c) {
      L[Lanes::kF + c][e] = out.f[c];
      L[Lanes::kC + c][e] = out.c[c];
    }
    for (int c = 0; c < kH; ++c) L[Lanes::kHist + c][e] = h[c];
    L[Lanes::kState][e] = (on ? Lanes::kOn : 0.0) + (k.delta > 0.0 ? Lanes::kTouch : 0.0);
  }

  // All entries of the lanes; more lanes per instruction where the CPU has them.
  template <bool kWall, bool kUniform, bool kUpdate>
  GRAINFLOW_DEM_SIMD_CLONES void evaluate_lanes(const Lanes& L, const Params& uniform_params, double dt) const {
#pragma omp simd
    for (std::size_t e = 0; e < L.n; ++e) evaluate_lane<kWall, kUniform, kUpdate>(L, e, uniform_params, dt);
  }

  // Compile-time `update` and, when all type pairs of the kind alike (one group),
  // loop-invariant parameters (a local copy, which the lanes' stores cannot alias): the
  // loop body is then free of control flow.
  template <bool kWall>
  void evaluate_all(const Lanes& L, bool update, double dt) const {
    const bool uniform = kWall ? uniform_wall_ : uniform_;
    const Params uniform_params = params_[kWall ? type_pair(0, kWallType) : type_pair(0, 0)];
    if (uniform && update) evaluate_lanes<kWall, true, true>(L, uniform_params, dt);
    else if (uniform) evaluate_lanes<kWall, true, false>(L, uniform_params, dt);
    else if (update) evaluate_lanes<kWall, false, true>(L, uniform_params, dt);
    else evaluate_lanes<kWall, false, false>(L, uniform_params, dt);
  }

  void pair_pass(const ForcePass& fp, std::size_t i0, std::size_t i1, double* virial) const override {
    const Box& b = *fp.box;
    if (b.periodic[0] || b.periodic[1] || b.periodic[2]) pair_loop<true>(fp, i0, i1, virial);
    else pair_loop<false>(fp, i0, i1, virial);  // all shifts are zero: skip the image look-up
  }

  template <bool kPeriodic>
  void pair_loop(const ForcePass& fp, std::size_t i0, std::size_t i1, double* virial) const {
    Particles& p = *fp.p;
    NeighborList& L = *fp.list;
    const double* __restrict x = p.x.data();
    const double* __restrict v = p.v.data();
    const double* __restrict w = p.w.data();
    const double* __restrict rad = p.radius.data();
    const double* __restrict m = p.mass.data();
    const std::uint8_t* __restrict grp = p.group.data();
    const std::uint32_t* __restrict first = L.first.data();
    const std::uint32_t* __restrict partner = L.partner.data();
    const std::uint32_t* __restrict owner = L.owner.data();
    const double* __restrict reach_sq = L.reach_sq.data();
    const std::uint8_t* __restrict shift = L.shift.data();
    std::uint8_t* __restrict flags = L.flags.data();
    double* __restrict hist = L.hist.data();
    const std::uint32_t* __restrict cross_slot = L.cross_slot.data();
    double* __restrict cross = L.cross_force.data();
    // A cross pair (j in a later chunk) that stops being active clears its slot.
    const auto clear_slot = [&](std::size_t q) {
      if (partner[q] >= i1) std::fill_n(cross + 6 * std::size_t(cross_slot[q]), 6, 0.0);
    };
    const auto& shifts = fp.box->shift;
    const bool update = fp.update;
    double* __restrict fsum = p.f.data();
    double* __restrict csum = p.t.data();
    // Phase 1: range test for every pair of the chunk, one flat loop over the pairs (no
    // per-particle inner loop whose varying length the branch predictor would miss);
    // pairs in range are listed in ascending q, i.e. per owner i by ascending j. Phase 2
    // evaluates only those, so the heavy contact code is not interleaved with the cheap
    // rejections.
    thread_local std::vector<std::uint32_t> in_range_buf;
    const std::uint32_t q0 = first[i0], q1 = first[i1];
    if (in_range_buf.size() < q1 - q0) in_range_buf.resize(q1 - q0);
    std::uint32_t* __restrict in_range = in_range_buf.data();
    std::uint32_t nin = 0;
    // size_t indices: 3·i and 3·j then fold into the addressing (no 32-bit wrap to honour).
    for (std::size_t q = q0; q < q1; ++q) {
      const std::size_t i = owner[q], j = partner[q];
      // x and y as one two-lane vector (fewer instructions in this loop-bound pass); the
      // same operations as in scalars: dx·dx + dy·dy + dz·dz.
      Pair dxy = load_pair(x + 3 * j) - load_pair(x + 3 * i);
      double dz = x[3 * j + 2] - x[3 * i + 2];
      if constexpr (kPeriodic) {
        const double* sh = shifts[shift[q]];
        dxy += load_pair(sh);
        dz += sh[2];
      }
      dxy *= dxy;
      const double rsq = dxy[0] + dxy[1] + dz * dz;
      // Branch-free listing: whether a listed pair touches is close to a coin toss.
      const bool in = rsq < reach_sq[q];
      in_range[nin] = static_cast<std::uint32_t>(q);
      nin += in;
      const std::uint8_t fl = flags[q];
      // Out of range with a flag set: a contact (or cohesion) just ended — rare.
      if (in || fl == 0) [[likely]] continue;
      if (update && (fl & NeighborList::kHistory)) {
        double* h = kH > 0 ? hist + q * kH : nullptr;
        for (int c = 0; c < kH; ++c) h[c] = 0.0;
        flags[q] = 0;
      } else {
        flags[q] = fl & static_cast<std::uint8_t>(~NeighborList::kActive);
      }
      clear_slot(q);
    }
    // Phase 2, block by block: the inputs of the pairs in range are gathered into the
    // lanes, evaluated in SIMD (they are independent: no sum is formed there), and the
    // outputs summed in entry order. Partners inside the chunk receive their share at once
    // (this chunk is the only writer of its particles); the others through the pair slots,
    // which the caller gathers once this pair pass is done. Each particle's sums run in a fixed
    // order: shares from owners earlier in the chunk (ascending owner), then its own pairs
    // (ascending j).
    std::fill(fsum + 3 * i0, fsum + 3 * i1, 0.0);
    std::fill(csum + 3 * i0, csum + 3 * i1, 0.0);
    for (std::uint32_t b0 = 0; b0 < nin; b0 += Lanes::kBlock) {
      const Lanes lanes = lane_block(std::min<std::size_t>(Lanes::kBlock, nin - b0));
      const std::uint32_t* __restrict entry = in_range + b0;
      for (std::size_t e = 0; e < lanes.n; ++e) {
        const std::size_t q = entry[e], i = owner[q], j = partner[q];
        double dx = x[3 * j] - x[3 * i], dy = x[3 * j + 1] - x[3 * i + 1], dz = x[3 * j + 2] - x[3 * i + 2];
        if constexpr (kPeriodic) {
          const double* sh = shifts[shift[q]];
          dx += sh[0];
          dy += sh[1];
          dz += sh[2];
        }
        const double ri = rad[i], rj = rad[j];
        lanes[Lanes::kDx][e] = dx;
        lanes[Lanes::kDy][e] = dy;
        lanes[Lanes::kDz][e] = dz;
        lanes[Lanes::kRi][e] = ri;
        lanes[Lanes::kRj][e] = rj;
        for (int c = 0; c < 3; ++c) {
          lanes[Lanes::kVr + c][e] = v[3 * i + c] - v[3 * j + c];
          lanes[Lanes::kW + c][e] = ri * w[3 * i + c] + rj * w[3 * j + c];
        }
        lanes[Lanes::kMi][e] = m[i];
        lanes[Lanes::kMj][e] = m[j];
        lanes[Lanes::kType][e] = type_pair(grp[i], grp[j]);
        for (int c = 0; c < kH; ++c) lanes[Lanes::kHist + c][e] = hist[q * kH + c];
      }
      evaluate_all<false>(lanes, update, fp.dt);
      for (std::size_t e = 0; e < lanes.n; ++e) {
        const std::size_t q = entry[e], i = owner[q], j = partner[q];
        if (update)
          for (int c = 0; c < kH; ++c) hist[q * kH + c] = lanes[Lanes::kHist + c][e];
        std::uint8_t fl = flags[q];
        const double st = lanes[Lanes::kState][e];
        if (st >= Lanes::kOn) {
          double o[6];
          for (int c = 0; c < 3; ++c) {
            o[c] = lanes[Lanes::kF + c][e];
            o[3 + c] = lanes[Lanes::kC + c][e];
          }
          fsum[3 * i] += o[0]; fsum[3 * i + 1] += o[1]; fsum[3 * i + 2] += o[2];
          csum[3 * i] += o[3]; csum[3 * i + 1] += o[4]; csum[3 * i + 2] += o[5];
          if (virial) {
            // r_ij = x_i − x_j: minus the lanes' separation x_j − x_i (its periodic image).
            const double r[3] = {-lanes[Lanes::kDx][e], -lanes[Lanes::kDy][e], -lanes[Lanes::kDz][e]};
            add_virial(virial, r, o);
          }
          // Partner in the chunk: scatter now, else fill the pair's slot (rare: a branch
          // costs less than writing both targets).
          if (j < i1) [[likely]] {
            fsum[3 * j] -= o[0]; fsum[3 * j + 1] -= o[1]; fsum[3 * j + 2] -= o[2];
            csum[3 * j] += o[3]; csum[3 * j + 1] += o[4]; csum[3 * j + 2] += o[5];
          } else {
            std::copy(o, o + 6, cross + 6 * std::size_t(cross_slot[q]));
          }
          fl |= NeighborList::kActive;
          if (update && st >= Lanes::kOn + Lanes::kTouch) fl |= NeighborList::kHistory;
        } else {
          fl = update ? 0 : fl & static_cast<std::uint8_t>(~NeighborList::kActive);
          clear_slot(q);
        }
        flags[q] = fl;
      }
    }
  }

  void wall_pass(const ForcePass& fp, std::size_t i0, std::size_t i1, double wall_sum[6][3],
                 double* virial) const override {
    const Box& box = *fp.box;
    Particles& p = *fp.p;
    const double range = range_;
    const bool update = fp.update;
    const double* __restrict x = p.x.data();
    const double* __restrict rad = p.radius.data();
    const std::uint32_t* __restrict slot = fp.wall_slot;
    std::uint8_t* __restrict flags = fp.wall_flags;
    double* __restrict hist = fp.wall_hist;
    // The particle–wall analogue of pair_loop: distance test for the walls in reach
    // (ascending i, then w), contacts evaluated in SIMD lanes, sums in that order.
    const std::uint32_t k0 = fp.wall_first[i0], k1 = fp.wall_first[i1];
    thread_local std::vector<std::uint32_t> in_range_buf;
    if (in_range_buf.size() < k1 - k0) in_range_buf.resize(k1 - k0);
    std::uint32_t* __restrict in_range = in_range_buf.data();
    const auto dist_of = [&](std::size_t s) {
      const std::size_t i = s / 6, wl = s % 6, a = wl / 2;
      return wl % 2 == 0 ? x[3 * i + a] - box.lo[a] : box.hi[a] - x[3 * i + a];
    };
    std::uint32_t nin = 0;
    for (std::uint32_t k = k0; k < k1; ++k) {
      const std::size_t s = slot[k];
      const bool in = !(dist_of(s) >= rad[s / 6] + range);
      in_range[nin] = static_cast<std::uint32_t>(s);
      nin += in;
      if (in || flags[s] == 0 || !update) continue;
      for (int c = 0; c < kH; ++c) hist[s * kH + c] = 0.0;  // contact over: forget its history
      flags[s] = 0;
    }
    for (std::uint32_t b0 = 0; b0 < nin; b0 += Lanes::kBlock) {
      const Lanes lanes = lane_block(std::min<std::size_t>(Lanes::kBlock, nin - b0));
      const std::uint32_t* __restrict entry = in_range + b0;
      for (std::size_t e = 0; e < lanes.n; ++e) {
        const std::size_t s = entry[e], i = s / 6, wl = s % 6, a = wl / 2;
        const double ri = rad[i];
        for (std::size_t c = 0; c < 3; ++c) lanes[Lanes::kDx + c][e] = c != a ? 0.0 : wl % 2 == 0 ? -1.0 : 1.0;
        lanes[Lanes::kRi][e] = ri;
        lanes[Lanes::kRj][e] = dist_of(s);
        for (int c = 0; c < 3; ++c) {
          lanes[Lanes::kVr + c][e] = p.v[3 * i + c] - box.wall_vel[wl][c];
          lanes[Lanes::kW + c][e] = ri * p.w[3 * i + c];
        }
        lanes[Lanes::kMi][e] = p.mass[i];
        lanes[Lanes::kType][e] = type_pair(p.group[i], kWallType);
        for (int c = 0; c < kH; ++c) lanes[Lanes::kHist + c][e] = hist[s * kH + c];
      }
      evaluate_all<true>(lanes, update, fp.dt);
      for (std::size_t e = 0; e < lanes.n; ++e) {
        const std::size_t s = entry[e], i = s / 6, wl = s % 6;
        if (update)
          for (int c = 0; c < kH; ++c) hist[s * kH + c] = lanes[Lanes::kHist + c][e];
        const double st = lanes[Lanes::kState][e];
        if (st >= Lanes::kOn) {
          const double ri = rad[i];
          if (virial) {
            // The centre relative to its foot on the wall: −(unit normal towards the wall) × distance.
            const double d = lanes[Lanes::kRj][e];
            const double r[3] = {-d * lanes[Lanes::kDx][e], -d * lanes[Lanes::kDy][e], -d * lanes[Lanes::kDz][e]};
            const double f[3] = {lanes[Lanes::kF][e], lanes[Lanes::kF + 1][e], lanes[Lanes::kF + 2][e]};
            add_virial(virial, r, f);
          }
          for (int c = 0; c < 3; ++c) {
            const double f = lanes[Lanes::kF + c][e];
            p.f[3 * i + c] += f;
            p.t[3 * i + c] += ri * lanes[Lanes::kC + c][e];
            wall_sum[wl][c] -= f;  // force on the wall
          }
          if (update && st >= Lanes::kOn + Lanes::kTouch) flags[s] |= NeighborList::kHistory;
        } else if (update) {
          flags[s] = 0;
        }
      }
    }
  }

private:
  Params params_[9];
  double range_ = 0.0;
  bool uniform_ = false;       // every particle–particle type pair has the parameters of params_[0]
  bool uniform_wall_ = false;  // both groups have the same wall parameters
};

}  // namespace

// The chosen row of each table becomes a template argument: every composition is compiled
// (the contact loop inlines its sub-models), and the spec picks one at run time.
std::unique_ptr<ContactLaw> make_contact_law(const ContactModelSpec& spec, const std::array<ContactParams, 9>& per,
                                             const std::array<double, 9>& meff) {
  require_composable(spec);
  return visit_model(spec.normal, [&]<class N>(std::type_identity<N>) {
    return visit_model(spec.tangential, [&]<class T>(std::type_identity<T>) {
      return visit_model(spec.cohesion, [&]<class C>(std::type_identity<C>) -> std::unique_ptr<ContactLaw> {
        if constexpr (kComposable<N, T, C>) return std::make_unique<ComposedLaw<N, T, C>>(per, meff);
        else return nullptr;  // refused by require_composable above; never compiled as a law
      });
    });
  });
}

}  // namespace grainflow::dem
