#include "scenes/src/studies/couette.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "render/snapshot.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/engines/sampling.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes::studies {
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

CouetteInput measure_couette(const Scene& sc, const CouetteRun& run) {
  if (sc.engine() != "ed") throw Error("couette: the scene must be an ED scene (run.engine = \"ed\")");
  const auto periodic = sc.get(ed_keys::periodic);
  if (periodic[1] || !periodic[0])
    throw Error("couette: the scene needs walls in y and a periodic x axis (boundary.periodic = [true, false])");
  const double until = sc.get(run_keys::until);
  const double exposure = sc.get(sample_keys::exposure);
  const auto box = sc.get(ed_keys::box);
  if (!(run.skip >= 0.0) || run.skip + 2 * exposure > until + 1e-9 * until)
    throw Error(fmt::format("couette: skip = {} leaves fewer than 2 exposures of {} before run.until = {}", run.skip,
                            exposure, until));
  if (!(run.bulk_fraction > 0.0 && run.bulk_fraction <= 1.0))
    throw Error(fmt::format("couette: bulk fraction {} is invalid; allowed: 0 < f <= 1", run.bulk_fraction));

  std::unique_ptr<EngineRunner> runner = find_engine("ed")->make_runner(sc);
  const std::vector<StatsColumn> columns = runner->stats_columns();
  auto column = [&](std::string_view name) {
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (columns[c].name == name) return c;
    throw Error(fmt::format("couette: the run has no stats column {}", name));
  };
  const std::size_t c_low = column("wall_fx_low"), c_high = column("wall_fx_high"), c_kT = column("kT");

  CouetteInput in;
  in.bulk_lo = 0.5 * box[1] * (1.0 - run.bulk_fraction);
  in.bulk_hi = box[1] - in.bulk_lo;
  // The disks' mass: 1 (σ = m = 1 units) unless the initial file says otherwise.
  core::ParticleFrame f;
  runner->particles(f);
  if (const std::vector<double>* m = f.column("mass"); m && !m->empty()) in.mass = (*m)[0];

  auto advance = [&](double t) {
    while (runner->time() < t) runner->advance_to(t);
  };
  // Block k covers the exposure [k τ_E, (k+1) τ_E]; the first wholly after skip.
  const long long first = (long long)std::ceil(run.skip / exposure - 1e-9);
  const long long last = (long long)std::floor(until / exposure + 1e-9);
  // A hair past each exposure's end, so that the sampler's event due then has run.
  const double hair = 1e-9 * exposure;
  advance(double(first) * exposure + hair);
  render::Snapshot s;
  runner->snapshot("uniform", s);  // drops the exposures before the first block
  runner->stats_row();             // starts the stats window with the first block
  for (long long k = first; k < last; ++k) {
    advance(double(k + 1) * exposure + hair);
    runner->snapshot("uniform", s);
    const std::vector<double> row = runner->stats_row();
    const render::NamedField* density = s.field("density");
    if (!s.velocity || !density) throw Error("couette: the sampler gave no velocity or density field");
    const core::GridGeometry& g = density->field.grid;
    if (in.y.empty())
      for (int iy = 0; iy < g.ny; ++iy) in.y.push_back(g.centre(0, iy).y());
    CouetteBlock b;
    b.ux.assign(std::size_t(g.ny), kNaN);
    b.density.assign(std::size_t(g.ny), kNaN);
    for (int iy = 0; iy < g.ny; ++iy) {
      // Mass-weighted x average of the row (the bins' velocities are mass-weighted means).
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
        b.ux[std::size_t(iy)] = nu / n;
        b.density[std::size_t(iy)] = n / bins;
      }
    }
    b.fx_low = row[c_low];
    b.fx_high = row[c_high];
    b.kT = row[c_kT];
    in.blocks.push_back(std::move(b));
    if (run.progress)
      std::fprintf(stderr, "couette: block %lld/%lld t = %.6g  stress = %.4g  kT = %.4g\n", k - first + 1,
                   last - first, runner->time(), 0.5 * (row[c_high] - row[c_low]), row[c_kT]);
  }
  return in;
}

std::string couette_report(const CouetteInput& in, const CouetteResult& r) {
  std::string out;
  auto line = [&](const char* name, const Estimate& e, const char* unit) {
    out += fmt::format("{:<12} = {:.6g} ± {:.2g}  {}\n", name, e.value, e.error, unit);
  };
  line("nu", r.nu, "σ²/τ (kinematic viscosity)");
  line("eta", r.eta, "m/τ (shear viscosity ρν)");
  line("stress", r.stress, "m/τ² (σ_xy, mean of both walls)");
  line("stress_low", r.stress_low, "m/τ² (−fx of the wall at y = 0)");
  line("stress_high", r.stress_high, "m/τ² (fx of the wall at y = Ly)");
  line("gradient", r.gradient, "1/τ (bulk du_x/dy)");
  line("density", r.density, "m/σ² (bulk)");
  line("kT", r.kT, "m σ²/τ² (whole box)");
  out += fmt::format("blocks = {}, bulk = [{:.6g}, {:.6g}] ({} bins)\n", r.blocks, in.bulk_lo, in.bulk_hi,
                     r.bulk_bins);
  out += "# y  u_x  error\n";
  for (std::size_t j = 0; j < in.y.size(); ++j)
    out += fmt::format("{:.6g} {:.6g} {:.3g}\n", in.y[j], r.profile[j], r.profile_error[j]);
  return out;
}

}  // namespace grainflow::scenes::studies
