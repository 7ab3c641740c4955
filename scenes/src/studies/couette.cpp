#include "scenes/src/studies/couette.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <limits>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"
#include "render/snapshot.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/engines/sampling.hpp"
#include "scenes/src/outputs/stats_csv.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/toml_text.hpp"
#include "scenes/src/studies/study.hpp"
#include "scenes/src/studies/study_table.hpp"

namespace grainflow::scenes {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / double(v.size());
}

// Covariance of the means of a and b over the blocks (the sample covariance / B).
double cov_of_means(const std::vector<double>& a, const std::vector<double>& b) {
  const double ma = mean(a), mb = mean(b);
  double s = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) s += (a[k] - ma) * (b[k] - mb);
  return s / double(a.size() - 1) / double(a.size());
}

Estimate estimate(const std::vector<double>& v) { return {mean(v), std::sqrt(cov_of_means(v, v))}; }

}  // namespace

CouetteResult analyse_couette(const CouetteInput& in) {
  const std::size_t nb = in.blocks.size(), ny = in.y.size();
  if (nb < 2) throw Error(fmt::format("couette: {} time block(s); allowed: at least 2 (for the error)", nb));
  std::vector<std::size_t> bulk;
  for (std::size_t j = 0; j < ny; ++j)
    if (in.y[j] >= in.bulk_lo && in.y[j] <= in.bulk_hi) bulk.push_back(j);
  if (bulk.size() < 2)
    throw Error(fmt::format("couette: {} bin(s) lie in the bulk [{}, {}]; allowed: at least 2 (more bins or a wider "
                            "bulk)", bulk.size(), in.bulk_lo, in.bulk_hi));
  // Least-squares slope over the bulk bins: Σ (y − ȳ) u / Σ (y − ȳ)².
  double ybar = 0.0;
  for (std::size_t j : bulk) ybar += in.y[j];
  ybar /= double(bulk.size());
  double syy = 0.0;
  for (std::size_t j : bulk) syy += (in.y[j] - ybar) * (in.y[j] - ybar);

  std::vector<double> stress(nb), s_low(nb), s_high(nb), grad(nb), rho(nb), kT(nb);
  CouetteResult r;
  r.profile.assign(ny, 0.0);
  r.profile_error.assign(ny, 0.0);
  std::vector<double> sum2(ny, 0.0);
  std::vector<std::size_t> filled(ny, 0);
  for (std::size_t k = 0; k < nb; ++k) {
    const CouetteBlock& b = in.blocks[k];
    if (b.ux.size() != ny || b.density.size() != ny)
      throw Error(fmt::format("couette: block {} has {} velocities and {} densities for {} bins", k, b.ux.size(),
                              b.density.size(), ny));
    double sxu = 0.0, n = 0.0;
    for (std::size_t j : bulk) {
      if (!std::isfinite(b.ux[j]) || !std::isfinite(b.density[j]))
        throw Error(fmt::format("couette: bulk bin {} (y = {}) is empty in block {}", j, in.y[j], k));
      sxu += (in.y[j] - ybar) * b.ux[j];
      n += b.density[j];
    }
    grad[k] = sxu / syy;
    rho[k] = in.mass * n / double(bulk.size());
    s_low[k] = -b.fx_low;
    s_high[k] = b.fx_high;
    stress[k] = 0.5 * (b.fx_high - b.fx_low);
    kT[k] = b.kT;
    for (std::size_t j = 0; j < ny; ++j)
      if (std::isfinite(b.ux[j])) {
        r.profile[j] += b.ux[j];
        sum2[j] += b.ux[j] * b.ux[j];
        ++filled[j];
      }
  }
  for (std::size_t j = 0; j < ny; ++j) {
    const double c = double(filled[j]);
    if (filled[j] == 0) {
      r.profile[j] = r.profile_error[j] = kNaN;
      continue;
    }
    r.profile[j] /= c;
    r.profile_error[j] = filled[j] > 1 ? std::sqrt(std::max(0.0, sum2[j] / c - r.profile[j] * r.profile[j]) *
                                                   c / (c - 1) / c)
                                       : kNaN;
  }
  r.blocks = nb;
  r.bulk_bins = bulk.size();
  r.stress = estimate(stress);
  r.stress_low = estimate(s_low);
  r.stress_high = estimate(s_high);
  r.gradient = estimate(grad);
  r.density = estimate(rho);
  r.kT = estimate(kT);
  r.bulk_y = ybar;
  for (std::size_t j : bulk) r.bulk_u += r.profile[j];
  r.bulk_u /= double(bulk.size());
  if (r.gradient.value == 0.0) throw Error("couette: the mean bulk velocity gradient is 0 (walls at rest?)");
  // ν = σ/(ρ g), η = σ/g; delta method: relative variance from the covariances of the means.
  const double s = r.stress.value, g = r.gradient.value, d = r.density.value;
  const double vs = cov_of_means(stress, stress) / (s * s), vg = cov_of_means(grad, grad) / (g * g),
               vd = cov_of_means(rho, rho) / (d * d);
  const double csg = cov_of_means(stress, grad) / (s * g), csd = cov_of_means(stress, rho) / (s * d),
               cgd = cov_of_means(grad, rho) / (g * d);
  r.eta.value = s / g;
  r.eta.error = std::abs(r.eta.value) * std::sqrt(std::max(0.0, vs + vg - 2 * csg));
  r.nu.value = s / (d * g);
  r.nu.error = std::abs(r.nu.value) * std::sqrt(std::max(0.0, vs + vg + vd - 2 * csg - 2 * csd + 2 * cgd));
  return r;
}

namespace {

// Optional keys (so that another study's scene setting them is refused); their defaults:
inline constexpr Key<double> skip{"study.skip"};
inline constexpr Key<double> bulk_fraction{"study.bulk_fraction"};
constexpr double kSkip = 2000.0, kBulkFraction = 0.5;

// One exposure's x-averaged profile (the frame that closes it), before its stats rows are
// matched to it in result().
struct Exposure {
  double t_begin = 0, t_end = 0;
  std::vector<double> ux, density;
};

class CouetteStudy final : public Study {
public:
  explicit CouetteStudy(const StudyContext& c)
      : rows_("couette", c.stats_columns, {"wall_fx_low", "wall_fx_high", "kT"}),
        skip_(c.scene.find(skip).value_or(kSkip)),
        bulk_(c.scene.find(bulk_fraction).value_or(kBulkFraction)),
        ly_(c.scene.get(ed_keys::box)[1]),
        walls_U_(c.scene.get(ed_keys::walls_U)),
        kT_(c.scene.get(ed_keys::kT)) {}

  void stats(double time, std::span<const double> row) override { rows_.add(time, row); }

  // Each frame carries the exposure that ended most recently: those starting after skip
  // are blocks. The profile is the mass-weighted x average of each row of bins.
  void frame(std::int64_t, const render::Snapshot& s) override {
    if (!s.exposure || s.exposure->t_begin < skip_ - 1e-9 * std::max(1.0, skip_)) return;
    if (!exposures_.empty() && s.exposure->t_end <= exposures_.back().t_end) return;  // the same one again
    const render::NamedField* density = s.field("density");
    if (!s.velocity || !density) throw Error("couette study: the sampler gave no velocity or density field");
    const core::GridGeometry& g = density->field.grid;
    if (y_.empty())
      for (int iy = 0; iy < g.ny; ++iy) y_.push_back(g.centre(0, iy).y());
    Exposure e;
    e.t_begin = s.exposure->t_begin;
    e.t_end = s.exposure->t_end;
    e.ux.assign(std::size_t(g.ny), kNoError);
    e.density.assign(std::size_t(g.ny), kNoError);
    for (int iy = 0; iy < g.ny; ++iy) {
      double n = 0.0, nu = 0.0;
      int bins = 0;
      for (int ix = 0; ix < g.nx; ++ix) {
        const std::size_t i = g.index(ix, iy);
        if (!density->field.mask[i] || !s.velocity->mask[i]) continue;
        n += density->field.values[i];
        nu += density->field.values[i] * s.velocity->values[i].x();
        ++bins;
      }
      if (bins > 0 && n > 0) {
        e.ux[std::size_t(iy)] = nu / n;
        e.density[std::size_t(iy)] = n / bins;
      }
    }
    exposures_.push_back(std::move(e));
  }

  void save(io::ArchiveWriter& w) const override {
    rows_.save(w);
    w.tag("couette.exposures");
    w.array(y_);
    w.pod(std::uint64_t(exposures_.size()));
    for (const Exposure& e : exposures_) {
      w.pod(e.t_begin);
      w.pod(e.t_end);
      w.array(e.ux);
      w.array(e.density);
    }
  }
  void load(io::ArchiveReader& r) override {
    rows_.load(r);
    r.tag("couette.exposures");
    r.array(y_);
    const auto n = r.get<std::uint64_t>();
    if (n > r.left()) r.corrupt("the couette study's " + std::to_string(n) + " exposures");
    exposures_.assign(std::size_t(n), {});
    for (Exposure& e : exposures_) {
      r.pod(e.t_begin);
      r.pod(e.t_end);
      r.array_of(e.ux, y_.size(), "an exposure's velocity profile");
      r.array_of(e.density, y_.size(), "an exposure's density profile");
    }
  }

  StudyResult result() const override {
    // Each exposure with the stats rows whose windows tile it (the rows' windows are equal
    // and the scene check makes the exposure a whole number of them): their mean forces.
    const auto& t = rows_.time();
    CouetteInput in;
    in.y = y_;
    in.bulk_lo = 0.5 * ly_ * (1.0 - bulk_);
    in.bulk_hi = ly_ - in.bulk_lo;
    in.mass = 1.0;  // σ = m = 1: the lattice's disks (the scene check refuses particle files)
    for (const Exposure& e : exposures_) {
      const double eps = 1e-9 * std::max(1.0, e.t_end);
      CouetteBlock b;
      b.ux = e.ux;
      b.density = e.density;
      int rows = 0;
      for (std::size_t i = 0; i < t.size(); ++i)
        if (t[i] > e.t_begin + eps && t[i] <= e.t_end + eps) {
          b.fx_low += rows_.column("wall_fx_low")[i];
          b.fx_high += rows_.column("wall_fx_high")[i];
          b.kT += rows_.column("kT")[i];
          ++rows;
        }
      if (rows == 0) continue;  // the run stopped before the exposure's row (cannot happen: rows come first)
      b.fx_low /= rows;
      b.fx_high /= rows;
      b.kT /= rows;
      in.blocks.push_back(std::move(b));
    }
    if (in.blocks.size() < 2)
      throw Error("couette study: " + std::to_string(in.blocks.size()) + " exposure(s) after study.skip = " +
                  std::to_string(skip_) + "; it needs at least 2 (a longer run.until or a smaller study.skip)");
    const CouetteResult r = analyse_couette(in);

    StudyResult res;
    auto add = [&](const char* name, const Estimate& e, const char* unit, const char* doc) {
      res.values.push_back({name, e.value, e.error, unit, doc});
    };
    res.values.push_back({"U_low", walls_U_[0], kNoError, "σ/τ", "x velocity of the wall at y = 0"});
    res.values.push_back({"U_high", walls_U_[1], kNoError, "σ/τ", "x velocity of the wall at y = Ly"});
    add("nu", r.nu, "σ²/τ", "kinematic viscosity σ_xy / (ρ du_x/dy) (delta method over the blocks)");
    add("eta", r.eta, "m/τ", "shear viscosity ρν = σ_xy / (du_x/dy)");
    add("stress", r.stress, "m/τ²", "shear stress σ_xy: mean of both walls' x forces per unit length");
    add("stress_low", r.stress_low, "m/τ²", "−wall_fx_low: the stress from the wall at y = 0 alone");
    add("stress_high", r.stress_high, "m/τ²", "wall_fx_high: the stress from the wall at y = Ly alone");
    add("gradient", r.gradient, "1/τ", "least-squares slope du_x/dy over the bulk bins");
    add("density", r.density, "m/σ²", "mass density in the bulk (m = 1)");
    add("kT", r.kT, "m σ²/τ²", "the gas's kT (whole box, stats rows of the blocks)");
    res.values.push_back({"blocks", double(r.blocks), kNoError, "", "exposures after study.skip, one block each"});
    res.values.push_back({"bulk_bins", double(r.bulk_bins), kNoError, "",
                          "y bins in the bulk (the middle study.bulk_fraction of the channel)"});
    // In the steady state both walls carry the same stress: a developing or drifting flow
    // shows as a difference beyond the errors.
    const double diff = r.stress_high.value - r.stress_low.value;
    const double diff_err = std::hypot(r.stress_high.error, r.stress_low.error);
    char detail[200];
    std::snprintf(detail, sizeof detail, "stress_high − stress_low = %.3g ± %.2g m/τ² (%.1f errors), allowed 3",
                  diff, diff_err, diff_err > 0 ? std::abs(diff) / diff_err : 0.0);
    res.checks.push_back({"both walls carry the same shear stress (steady state)", std::abs(diff) <= 3 * diff_err,
                          detail});
    res.notes.push_back("blocks of one exposure each; the error is their standard error, honest when an exposure is "
                        "much longer than the stress's correlation time; the seed gives ν ≈ 0.65 (§4.2)");
    if (std::abs(r.kT.value / kT_ - 1.0) > 0.05)
      res.notes.push_back("kT = " + std::to_string(r.kT.value) + " differs from system.kT = " + std::to_string(kT_) +
                          " by more than 5 %: viscous heating (ν depends on kT)");

    auto& f = res.figure;
    char title[200];
    std::snprintf(title, sizeof title, "Planar Couette flow, U = [%g, %g]: ν = %.3f ± %.2g σ²/τ (%zu blocks)",
                  walls_U_[0], walls_U_[1], r.nu.value, r.nu.error, r.blocks);
    f.title = title;
    f.x = {"y (σ)", false, {}};
    f.y = {"u_x (σ/τ)", false, {}};
    render::plot::Series profile, fit, walls;
    profile.label = "u_x(y), mean of the blocks ± standard error";
    profile.style = render::plot::SeriesStyle::points;
    profile.x = y_;
    profile.y = r.profile;
    for (double e : r.profile_error) profile.y_err.push_back(std::isfinite(e) ? e : 0.0);
    char label[160];
    std::snprintf(label, sizeof label, "bulk fit: du/dy = %.3g ± %.2g /τ", r.gradient.value, r.gradient.error);
    fit.label = label;
    fit.colour = render::Rgb{0.1f, 0.1f, 0.1f};
    fit.width_px = 1.5f;
    for (double y : {in.bulk_lo, in.bulk_hi}) {
      fit.x.push_back(y);
      fit.y.push_back(r.bulk_u + r.gradient.value * (y - r.bulk_y));
    }
    render::plot::Series extended = fit;
    extended.label = "the fit extended to the walls (their slip layers)";
    extended.dashed = true;
    extended.colour = render::Rgb{0.5f, 0.5f, 0.5f};
    extended.x = {0.0, ly_};
    extended.y = {r.bulk_u - r.gradient.value * r.bulk_y, r.bulk_u + r.gradient.value * (ly_ - r.bulk_y)};
    walls.label = "wall velocities";
    walls.style = render::plot::SeriesStyle::points;
    walls.colour = render::Rgb{0.84f, 0.15f, 0.16f};
    walls.x = {0.0, ly_};
    walls.y = {walls_U_[0], walls_U_[1]};
    f.series = {profile, extended, fit, walls};
    return res;
  }

private:
  StatsRows rows_;
  double skip_, bulk_, ly_;
  std::array<double, 2> walls_U_;
  double kT_;
  std::vector<double> y_;
  std::vector<Exposure> exposures_;
};

void declare(Schema& s) {
  s.table("study")
      .add_float(skip, kSkip, "couette: simulated time before the first block (the profile develops; exposures that "
                              "begin earlier are not used)", "τ")
      .at_least(0.0)
      .optional();
  s.table("study")
      .add_float(bulk_fraction, kBulkFraction,
                 "couette: the middle fraction of the channel (Ly) whose bins give the velocity gradient, away from "
                 "the walls' slip layers")
      .above(0.0)
      .at_most(1.0)
      .optional();
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(study_keys::study)) return;
    const bool mine = sc.get(study_keys::kind) == "couette";
    for (const auto* k : {&skip, &bulk_fraction})
      if (sc.has(*k) && !mine)
        c.fail(k->path, "is a key of the couette study; this scene's study is " + sc.get(study_keys::kind));
    if (!mine) return;
    if (sc.get(ed_keys::periodic)[1] || !sc.get(ed_keys::periodic)[0])
      c.fail(ed_keys::periodic.path, "the couette study shears the gas between walls in y, periodic in x: "
                                     "boundary.periodic = [true, false]");
    else if (!sc.has(ed_keys::walls) || sc.get(ed_keys::walls_U)[0] == sc.get(ed_keys::walls_U)[1])
      c.fail(study_keys::kind.path, "the couette study needs walls in y moving at different speeds: "
                                    "[boundary.walls] U = [U_low, U_high], U_low ≠ U_high");
    if (sc.has(ed_keys::obstacle))
      c.fail(ed_keys::obstacle.path, "the couette study is of a homogeneous channel; allowed: no [boundary.obstacle]");
    if (sc.get(ed_keys::initial_kind) != "lattice")
      c.fail(ed_keys::initial_kind.path, "the couette study takes the disks' mass as 1 (the lattice's); allowed: "
                                         "system.initial.kind = \"lattice\" (study.skip lets the lattice melt)");
    // A block is one exposure and the stats rows of exactly its interval.
    const double exposure = sc.get(sample_keys::exposure);
    const double every = sc.get(stats_keys::every) > 0 ? sc.get(stats_keys::every) : exposure;
    const double ratio = exposure / every;
    if (!(std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio) || ratio < 0.5)
      c.fail(stats_keys::every.path, "the couette study averages the wall forces over each exposure: "
                                     "sample.exposure = " + toml_float(exposure) + " must be a whole number of "
                                     "output.stats_every = " + toml_float(every) + " (0: one row per exposure)");
    if (const auto until = sc.find(run_keys::until); until && sc.find(skip).value_or(kSkip) + 2 * exposure > *until)
      c.fail(run_keys::until.path, "run.until = " + toml_float(*until) + " leaves fewer than 2 exposures of " +
                                       toml_float(exposure) + " after study.skip = " +
                                       toml_float(sc.find(skip).value_or(kSkip)) + "; the couette study needs at least 2");
  });
}

std::unique_ptr<Study> open(const StudyContext& c) { return std::make_unique<CouetteStudy>(c); }

}  // namespace

StudyEntry couette_study() {
  return {"couette", "kinematic viscosity from planar Couette flow: wall shear stress and bulk velocity profile "
                     "(seed 003 §4.2)",
          "ed", &declare, &open};
}

}  // namespace grainflow::scenes
