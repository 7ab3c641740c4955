#include "engine/dem/contact_law.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/dem/history_tangential.hpp"
#include "engine/dem/hooke_normal.hpp"
#include "engine/dem/vdw_cohesion.hpp"
#include "engine/dem/walton_normal.hpp"
#include "engine/dem/walton_tangential.hpp"

namespace grainflow::dem {

namespace {

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
  };

  ComposedLaw(const std::array<ContactParams, 9>& per, const std::array<double, 9>& meff) {
    for (int k = 0; k < 9; ++k) {
      params_[k] = {N::make(per[k], meff[k]), T::make(per[k], meff[k]), C::make(per[k], meff[k])};
      range_ = std::max(range_, C::range(params_[k].c));
    }
  }
  int history_size() const override { return kH; }
  double cohesion_range() const override { return range_; }

  bool evaluate(int tp, const ContactKinematics& k, double* h, bool update, ContactForce& out) const override {
    return eval(params_[tp], k, h, update, out);
  }

  static bool eval(const Params& q, const ContactKinematics& k, double* h, bool update, ContactForce& out) {
    double fn = 0.0, ft[3] = {0.0, 0.0, 0.0};
    if (k.delta > 0.0) {
      fn = N::force(q.n, k, h, update);
      T::force(q.t, k, fn, h + N::kHistory, update, ft);
    } else if (update) {
      for (int a = 0; a < kH; ++a) h[a] = 0.0;  // contact over: forget its history
    }
    const double fc = C::force(q.c, k);
    if (k.delta <= 0.0 && fc == 0.0) return false;
    const double fnet = fn - fc;  // repulsive along −n on particle i
    for (int a = 0; a < 3; ++a) out.f[a] = -fnet * k.n[a] + ft[a];
    out.c[0] = k.n[1] * ft[2] - k.n[2] * ft[1];
    out.c[1] = k.n[2] * ft[0] - k.n[0] * ft[2];
    out.c[2] = k.n[0] * ft[1] - k.n[1] * ft[0];
    return true;
  }

  void pair_pass(const ForcePass& fp, std::size_t i0, std::size_t i1) const override {
    const Box& b = *fp.box;
    if (b.periodic[0] || b.periodic[1] || b.periodic[2]) pair_loop<true>(fp, i0, i1);
    else pair_loop<false>(fp, i0, i1);  // all shifts are zero: skip the image look-up
  }

  template <bool kPeriodic>
  void pair_loop(const ForcePass& fp, std::size_t i0, std::size_t i1) const {
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
    const std::uint8_t* __restrict shift = L.shift.data();
    std::uint8_t* __restrict flags = L.flags.data();
    double* __restrict hist = L.hist.data();
    double* __restrict pforce = L.pair_force.data();
    const auto& shifts = fp.box->shift;
    const double range = range_;
    const bool update = fp.update;
    double* __restrict fsum = p.f.data();
    double* __restrict csum = p.t.data();
    // Phase 1: range test for every pair of the chunk (short, predictable loop); pairs in
    // range are listed in ascending q, i.e. per owner i by ascending j. Phase 2 evaluates
    // only those, so the heavy contact code is not interleaved with the cheap rejections.
    thread_local std::vector<std::uint32_t> in_range_buf, owner_buf;
    const std::uint32_t q0 = first[i0], q1 = first[i1];
    if (in_range_buf.size() < q1 - q0) {
      in_range_buf.resize(q1 - q0);
      owner_buf.resize(q1 - q0);
    }
    std::uint32_t* __restrict in_range = in_range_buf.data();
    std::uint32_t* __restrict owner = owner_buf.data();
    std::uint32_t nin = 0;
    for (std::size_t i = i0; i < i1; ++i) {
      const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2], ri = rad[i] + range;
      // size_t indices: 3·j then folds into the addressing (no 32-bit wrap to honour).
      const std::size_t qe = first[i + 1];
      for (std::size_t q = first[i]; q < qe; ++q) {
        const std::size_t j = partner[q];
        double dx = x[3 * j] - xi, dy = x[3 * j + 1] - yi, dz = x[3 * j + 2] - zi;
        if constexpr (kPeriodic) {
          const double* sh = shifts[shift[q]];
          dx += sh[0];
          dy += sh[1];
          dz += sh[2];
        }
        const double rsq = dx * dx + dy * dy + dz * dz;
        const double reach = ri + rad[j];
        // Branch-free listing: whether a listed pair touches is close to a coin toss.
        const bool in = rsq < reach * reach;
        in_range[nin] = static_cast<std::uint32_t>(q);
        owner[nin] = static_cast<std::uint32_t>(i);
        nin += in;
        const std::uint8_t fl = flags[q];
        // Out of range with a flag set: a contact (or cohesion) just ended — rare.
        if (in || fl == 0) [[likely]] continue;
        if (update && (fl & NeighborList::kHistory)) {
          double* h = kH > 0 ? hist + std::size_t(q) * kH : nullptr;
          for (int c = 0; c < kH; ++c) h[c] = 0.0;
          flags[q] = 0;
        } else {
          flags[q] = fl & static_cast<std::uint8_t>(~NeighborList::kActive);
        }
      }
    }
    // Phase 2: contacts (and cohesion within range). Partners inside the chunk receive
    // their share at once (this chunk is the only writer of its particles); the others
    // through the pair slots, gathered by the caller after all chunks are done.
    std::fill(fsum + 3 * i0, fsum + 3 * i1, 0.0);
    std::fill(csum + 3 * i0, csum + 3 * i1, 0.0);
    double scratch[12] = {};
    // Each particle's sums run in a fixed order: shares from owners earlier in the chunk
    // (ascending owner), then its own pairs (ascending j).
    for (std::uint32_t e = 0; e < nin; ++e) {
      const std::size_t q = in_range[e];
      const std::size_t i = owner[e];
      const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2], ri = rad[i];
      const std::size_t j = partner[q];
      double dx = x[3 * j] - xi, dy = x[3 * j + 1] - yi, dz = x[3 * j + 2] - zi;
      if constexpr (kPeriodic) {
        const double* sh = shifts[shift[q]];
        dx += sh[0];
        dy += sh[1];
        dz += sh[2];
      }
      const double rsq = dx * dx + dy * dy + dz * dz;
      const double rsum = ri + rad[j];
      double* h = kH > 0 ? hist + q * kH : nullptr;
      ContactKinematics k;
      const double r = std::sqrt(rsq), rinv = 1.0 / r;
      k.n[0] = dx * rinv;
      k.n[1] = dy * rinv;
      k.n[2] = dz * rinv;
      k.delta = rsum - r;
      const double vr[3] = {v[3 * i] - v[3 * j], v[3 * i + 1] - v[3 * j + 1], v[3 * i + 2] - v[3 * j + 2]};
      k.vn = vr[0] * k.n[0] + vr[1] * k.n[1] + vr[2] * k.n[2];
      const double rj = rad[j];
      const double W[3] = {ri * w[3 * i] + rj * w[3 * j], ri * w[3 * i + 1] + rj * w[3 * j + 1],
                           ri * w[3 * i + 2] + rj * w[3 * j + 2]};
      k.vt[0] = vr[0] - k.vn * k.n[0] + (W[1] * k.n[2] - W[2] * k.n[1]);
      k.vt[1] = vr[1] - k.vn * k.n[1] + (W[2] * k.n[0] - W[0] * k.n[2]);
      k.vt[2] = vr[2] - k.vn * k.n[2] + (W[0] * k.n[1] - W[1] * k.n[0]);
      // Reduced mass and radius cost a division each: only for sub-models that read them.
      k.m_eff = kNeedsMass ? m[i] * m[j] / (m[i] + m[j]) : 0.0;
      k.r_eff = C::kNeedsRadius ? ri * rj / rsum : 0.0;
      k.dt = fp.dt;
      k.wall = false;
      ContactForce out;
      const bool on = eval(params_[type_pair(grp[i], grp[j])], k, h, update, out);
      std::uint8_t fl = flags[q];
      if (on) {
        fsum[3 * i] += out.f[0]; fsum[3 * i + 1] += out.f[1]; fsum[3 * i + 2] += out.f[2];
        csum[3 * i] += out.c[0]; csum[3 * i + 1] += out.c[1]; csum[3 * i + 2] += out.c[2];
        // Partner in the chunk: scatter now, else store the pair slot; the unused
        // target is a scratch buffer, so no (poorly predicted) branch is needed.
        const bool local = j < i1;
        double* tf = local ? fsum + 3 * j : scratch;
        double* tc = local ? csum + 3 * j : scratch + 3;
        double* pf = local ? scratch + 6 : pforce + q * 6;
        tf[0] -= out.f[0]; tf[1] -= out.f[1]; tf[2] -= out.f[2];
        tc[0] += out.c[0]; tc[1] += out.c[1]; tc[2] += out.c[2];
        pf[0] = out.f[0]; pf[1] = out.f[1]; pf[2] = out.f[2];
        pf[3] = out.c[0]; pf[4] = out.c[1]; pf[5] = out.c[2];
        fl |= NeighborList::kActive;
        if (update && k.delta > 0.0) fl |= NeighborList::kHistory;
      } else {
        fl = update ? 0 : fl & static_cast<std::uint8_t>(~NeighborList::kActive);
      }
      flags[q] = fl;
    }
  }

  void wall_pass(const ForcePass& fp, std::size_t i0, std::size_t i1, double wall_sum[6][3]) const override {
    const Box& box = *fp.box;
    const double range = range_;
    const double* __restrict x = fp.p->x.data();
    const double* __restrict rad = fp.p->radius.data();
    const std::uint8_t* __restrict near = fp.wall_near;
    for (std::size_t i = i0; i < i1; ++i) {
      const std::uint8_t mask = near[i];
      if (mask == 0) [[likely]] continue;  // no wall within reach until the next rebuild
      const double ri = rad[i];
      for (unsigned bits = mask; bits != 0; bits &= bits - 1) {  // the flagged walls, ascending
        const int wl = std::countr_zero(bits);
        const int a = wl / 2, side = wl % 2;
        const double dist = side == 0 ? x[3 * i + a] - box.lo[a] : box.hi[a] - x[3 * i + a];
        if (dist >= ri + range) {
          std::uint8_t& fl = fp.wall_flags[6 * i + wl];
          if (fl != 0 && fp.update) {
            double* h = kH > 0 ? &fp.wall_hist[(6 * i + wl) * kH] : nullptr;
            for (int c = 0; c < kH; ++c) h[c] = 0.0;
            fl = 0;
          }
          continue;
        }
        wall_contact(fp, i, wl, a, side, dist, wall_sum);
      }
    }
  }

  void wall_contact(const ForcePass& fp, std::size_t i, int wl, int a, int side, double dist,
                    double wall_sum[6][3]) const {
    Particles& p = *fp.p;
    const Box& box = *fp.box;
    const double ri = p.radius[i];
    std::uint8_t& fl = fp.wall_flags[6 * i + wl];
    double* h = kH > 0 ? &fp.wall_hist[(6 * i + wl) * kH] : nullptr;
    ContactKinematics k;
    k.n[0] = k.n[1] = k.n[2] = 0.0;
    k.n[a] = side == 0 ? -1.0 : 1.0;
    k.delta = ri - dist;
    const double* wv = box.wall_vel[wl];
    const double vr[3] = {p.v[3 * i] - wv[0], p.v[3 * i + 1] - wv[1], p.v[3 * i + 2] - wv[2]};
    k.vn = vr[0] * k.n[0] + vr[1] * k.n[1] + vr[2] * k.n[2];
    const double W[3] = {ri * p.w[3 * i], ri * p.w[3 * i + 1], ri * p.w[3 * i + 2]};
    k.vt[0] = vr[0] - k.vn * k.n[0] + (W[1] * k.n[2] - W[2] * k.n[1]);
    k.vt[1] = vr[1] - k.vn * k.n[1] + (W[2] * k.n[0] - W[0] * k.n[2]);
    k.vt[2] = vr[2] - k.vn * k.n[2] + (W[0] * k.n[1] - W[1] * k.n[0]);
    k.m_eff = p.mass[i];
    k.r_eff = ri;
    k.dt = fp.dt;
    k.wall = true;
    ContactForce out;
    if (eval(params_[type_pair(p.group[i], kWallType)], k, h, fp.update, out)) {
      for (int c = 0; c < 3; ++c) {
        p.f[3 * i + c] += out.f[c];
        p.t[3 * i + c] += ri * out.c[c];
        wall_sum[wl][c] -= out.f[c];  // force on the wall
      }
      if (fp.update && k.delta > 0.0) fl |= NeighborList::kHistory;
    } else if (fp.update) {
      fl = 0;
    }
  }

private:
  Params params_[9];
  double range_ = 0.0;
};

template <class N, class T>
std::unique_ptr<ContactLaw> with_cohesion(CohesionKind c, const std::array<ContactParams, 9>& per,
                                          const std::array<double, 9>& meff) {
  switch (c) {
    case CohesionKind::None: return std::make_unique<ComposedLaw<N, T, NoCohesion>>(per, meff);
    case CohesionKind::VanDerWaals: return std::make_unique<ComposedLaw<N, T, VdwCohesion>>(per, meff);
  }
  throw Error("dem: unknown cohesion model");
}

template <class N>
std::unique_ptr<ContactLaw> with_tangential(TangentialKind t, CohesionKind c, const std::array<ContactParams, 9>& per,
                                            const std::array<double, 9>& meff) {
  switch (t) {
    case TangentialKind::Walton: return with_cohesion<N, WaltonTangential>(c, per, meff);
    case TangentialKind::History: return with_cohesion<N, HistoryTangential>(c, per, meff);
    case TangentialKind::None: return with_cohesion<N, NoTangential>(c, per, meff);
  }
  throw Error("dem: unknown tangential model");
}

}  // namespace

// Registration table: adding a sub-model = one header + one case here.
std::unique_ptr<ContactLaw> make_contact_law(const ContactModelSpec& spec, const std::array<ContactParams, 9>& per,
                                             const std::array<double, 9>& meff) {
  switch (spec.normal) {
    case NormalKind::Walton: return with_tangential<WaltonNormal>(spec.tangential, spec.cohesion, per, meff);
    case NormalKind::Hooke: return with_tangential<HookeNormal>(spec.tangential, spec.cohesion, per, meff);
  }
  throw Error("dem: unknown normal model");
}

}  // namespace grainflow::dem
