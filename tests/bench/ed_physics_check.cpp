// Statistical physics check of the ED hard-disk engine (seed 003 ch. 2 and §4.1): the
// equilibrium observables of the elastic periodic box with standard errors from
// independent runs, so that two builds (e.g. before and after a change of the engine's
// memory layout, which changes every trajectory bit) can be compared within statistics.
//
// Measured, each from K independent runs (different seeds; lattice start, equilibrated,
// then measured; the standard error is the spread of the K run means over sqrt(K)):
//   Z_eta*      Z = PA/(NkT) (collision virial) at η = 0.30 … 0.69, kT = 1, beside
//               Henderson 1975 and Liu 2020 (references below);
//   Zhalf_eta*  Z over the second half of the window minus the first half: an
//               equilibration check (0 within its error when the runs were equilibrated);
//   contact_eta* τ·4(Z − 1)/(σ sqrt(π m/kT)): 1 in equilibrium. Both Z − 1 = 2η g(σ) and
//               the Enskog collision rate 1/τ = 2nσ g(σ) sqrt(πkT/m) are exact for hard
//               disks in equilibrium (up to O(1/N) in a finite box of fixed energy and
//               momentum, ≈ 1 + 1/(2N)), so the mean free time and the pressure must agree
//               with each other whatever the equation of state;
//   tau_0.65    mean free time at η = 0.65, kT = 0.02 (seed 003 §4.1: 0.43);
//   energy/book/momentum drift over 10^6 collisions at η = 0.65, kT = 0.02, stream
//               U = (0.03, 0) (elastic: ≤ 1e-9), and no overlap at the end;
//   velocity moments at η = 0.65 after starting every disk at the same speed (one
//   component's kurtosis 1.5): kurtosis ⟨v_x⁴⟩/⟨v_x²⟩² (3, or 3D/(D + 2) for the D =
//   2N − 2 velocity components of a finite box of fixed energy and momentum),
//   ⟨v_x⁶⟩/⟨v_x²⟩³ (15), equipartition ⟨v_x²⟩/⟨v_y²⟩, and kT measured over set (≤ 1e-9).
// Conservation rows give the largest |value| over the runs against a bound, not an error.
// Run lengths are set in collisions per disk through the Henderson–Enskog estimate of τ
// (a fixed schedule in time, the same for every build): equilibration / measurement from
// 200 / 500 at η = 0.30 to 1500 / 3000 at η = 0.69 (N = 2000: Z settles after ≈ 800 there).
// Usage: ed_physics_check [--quick] [--seeds K] [--n N] [--compare FILE]
//   --quick    a fifth of the run lengths and 3 seeds (a smoke test, not a measurement)
//   --seeds K  independent runs per measurement (default 8; K ≥ 2 for error bars)
//   --n N      disks per box (default 2000)
//   --compare FILE  also compares every row with the same row of an earlier output (this
//              program's stdout) and prints z = Δ/sqrt(se₁² + se₂²); conservation rows are
//              checked against their bound instead.
// stdout is the same for the same build and options; wall times go to stderr.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

namespace {

constexpr double kPi = std::numbers::pi;

// Henderson 1975 (Mol. Phys. 30, 971), Eq. 5: the hard-disk fluid's Z.
double henderson_z(double eta) { return (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta)); }
// Liu 2020, "Global equation of state and phase transitions of the hard disc systems"
// (arXiv:2010.10624), Eq. 1, the stable-fluid branch, as its author gives it on SklogWiki
// (not checked against the paper itself). The paper adds a term for the approach to the
// liquid–hexatic transition (η ≈ 0.70), not reproduced here: at η = 0.69 neither fit is a
// reference, the row is for comparing builds.
double liu_z(double eta) {
  const double e2 = eta * eta;
  return (1.0 + e2 / 8.0 + e2 * eta / 18.0 - 4.0 * e2 * e2 / 21.0) / ((1.0 - eta) * (1.0 - eta));
}
// Mean free time from Z through the contact value (see the header): σ = m = 1.
double tau_from_z(double z, double kT) { return std::sqrt(kPi / kT) / (4.0 * (z - 1.0)); }

struct Options {
  bool quick = false;
  int seeds = 8;
  int n = 2000;
  std::string compare;
};

// A row of the table: mean ± standard error over the runs, or (bound > 0) the largest
// |value| over the runs, which must stay below the bound.
struct Row {
  std::string key, what;
  double mean = 0.0, se = 0.0;
  double bound = 0.0;
  std::vector<std::pair<std::string, double>> refs;
};

struct Sample {
  std::vector<double> v;
  void add(double x) { v.push_back(x); }
  double mean() const {
    double s = 0.0;
    for (double x : v) s += x;
    return s / v.size();
  }
  double se() const {
    if (v.size() < 2) return NAN;
    const double m = mean();
    double s = 0.0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / (v.size() - 1) / v.size());
  }
  double max_abs() const {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
  }
};

Row stat_row(std::string key, std::string what, const Sample& s,
             std::vector<std::pair<std::string, double>> refs = {}) {
  return Row{std::move(key), std::move(what), s.mean(), s.se(), 0.0, std::move(refs)};
}
Row bound_row(std::string key, std::string what, const Sample& s, double bound) {
  return Row{std::move(key), std::move(what), s.max_abs(), NAN, bound, {}};
}

// Square periodic box of n disks at area fraction eta (L from n, so η is exact).
ed::Config box(int n, double eta, double kT, std::uint64_t seed) {
  ed::Config c;
  c.n = n;
  c.lx = c.ly = std::sqrt(n * kPi / 4.0 / eta);
  c.area_fraction = eta;
  c.kT = kT;
  c.seed = seed;
  return c;
}

// Every disk present, brought to the current time: the one place that reads the engine's
// disk records (adapt it here if their layout changes).
struct DiskState {
  double x, y, vx, vy;
};
std::vector<DiskState> disk_states(ed::Simulation& sim) {
  sim.synchronise();
  std::vector<DiskState> out;
  out.reserve(sim.count());
  for (int i = 0; i < sim.size(); ++i)
    if (sim.present(i)) {
      const auto& d = sim.disks()[i];
      out.push_back({d.x, d.y, d.vx, d.vy});
    }
  return out;
}

// ---- 1, 2: equation of state, contact relation, mean free time --------------------------

struct EquilibriumRun {
  double z = 0.0, z_half_diff = 0.0, tau = 0.0;
};

// Equilibrates for eq_coll collisions per disk, measures over meas_coll more, in two halves;
// the lengths are set in time from the Henderson–Enskog estimate of τ (a fixed schedule,
// the same for every build).
EquilibriumRun equilibrium_run(const ed::Config& c, double eq_coll, double meas_coll) {
  const double tau_est = tau_from_z(henderson_z(c.area_fraction), c.kT);
  ed::Simulation sim(c);
  sim.run_until(eq_coll * tau_est);
  const double t0 = sim.time(), half = 0.5 * meas_coll * tau_est;
  sim.reset_measurements();
  sim.run_until(t0 + half);
  const ed::Observables a = sim.observables();
  sim.reset_measurements();
  sim.run_until(t0 + 2.0 * half);
  const ed::Observables b = sim.observables();
  EquilibriumRun r;
  // kT is conserved to round-off, so the two equal windows' Z average to the whole's.
  r.z = 0.5 * (a.compressibility + b.compressibility);
  r.z_half_diff = b.compressibility - a.compressibility;
  const double n = sim.count();
  r.tau = (a.duration + b.duration) * n / (2.0 * static_cast<double>(a.collisions + b.collisions));
  return r;
}

struct Density {
  double eta, eq_coll, meas_coll;  // collisions per disk
};

void equation_of_state(const Options& o, std::vector<Row>& rows) {
  // Run lengths: the collective relaxation slows with density (at η = 0.69 and N = 2000,
  // Z settles ≈ 800 collisions per disk after the lattice start), and so does the
  // convergence of Z per collision.
  const Density densities[] = {{0.30, 200, 500},   {0.40, 300, 700},   {0.50, 400, 1000},
                               {0.60, 600, 1500},  {0.65, 1000, 2000}, {0.69, 1500, 3000}};
  const double f = o.quick ? 0.2 : 1.0;
  std::vector<Row> z_rows, half_rows, contact_rows;
  for (std::size_t d = 0; d < std::size(densities); ++d) {
    const auto& ds = densities[d];
    Sample z, half, contact;
    for (int s = 0; s < o.seeds; ++s) {
      const auto r = equilibrium_run(box(o.n, ds.eta, 1.0, 1000 * (d + 1) + s), f * ds.eq_coll, f * ds.meas_coll);
      z.add(r.z);
      half.add(r.z_half_diff);
      contact.add(r.tau / tau_from_z(r.z, 1.0));
    }
    char key[64], what[128];
    std::snprintf(key, sizeof key, "Z_eta%.2f", ds.eta);
    std::snprintf(what, sizeof what, "Z = PA/(NkT), eta %.2f, kT 1", ds.eta);
    z_rows.push_back(stat_row(key, what, z, {{"Henderson75", henderson_z(ds.eta)}, {"Liu20", liu_z(ds.eta)}}));
    std::snprintf(key, sizeof key, "Zhalf_eta%.2f", ds.eta);
    std::snprintf(what, sizeof what, "Z(2nd half) - Z(1st half), eta %.2f", ds.eta);
    half_rows.push_back(stat_row(key, what, half, {{"equilibrated", 0.0}}));
    std::snprintf(key, sizeof key, "contact_eta%.2f", ds.eta);
    std::snprintf(what, sizeof what, "tau*4(Z-1)/sqrt(pi m/kT), eta %.2f", ds.eta);
    // The fixed total momentum alone makes the relative velocity's variance N/(N − 1)
    // times 2kT/m, and the ratio sqrt(N/(N − 1)); the rest of O(1/N) is not modelled.
    contact_rows.push_back(
        stat_row(key, what, contact, {{"exact", 1.0}, {"fixedP", std::sqrt(o.n / (o.n - 1.0))}}));
  }
  for (auto* v : {&z_rows, &half_rows, &contact_rows}) rows.insert(rows.end(), v->begin(), v->end());
}

void mean_free_time(const Options& o, std::vector<Row>& rows) {
  const double f = o.quick ? 0.2 : 1.0, eta = 0.65, kT = 0.02;
  Sample tau;
  for (int s = 0; s < o.seeds; ++s) tau.add(equilibrium_run(box(o.n, eta, kT, 7000 + s), f * 1000, f * 2000).tau);
  rows.push_back(stat_row("tau_eta0.65_kT0.02", "mean free time, eta 0.65, kT 0.02", tau,
                          {{"seed003", 0.43}, {"Liu20+contact", tau_from_z(liu_z(eta), kT)}}));
}

// ---- 3: conservation ----------------------------------------------------------------------

void conservation(const Options& o, std::vector<Row>& rows) {
  const std::uint64_t collisions = o.quick ? 200000 : 1000000;
  Sample energy, book, momentum, gap;
  const char* calendar = "";
  for (int s = 0; s < o.seeds; ++s) {
    ed::Config c = box(o.n, 0.65, 0.02, 8000 + s);
    c.stream = {0.03, 0.0};  // a moving box: the momentum books are not trivially zero
    ed::Simulation sim(c);
    calendar = sim.calendar();
    const double e0 = sim.kinetic_energy();
    const auto p0 = sim.momentum();
    while (sim.stats().collisions < collisions) sim.advance(100000);
    energy.add(sim.kinetic_energy() / e0 - 1.0);
    book.add(sim.state().kinetic() / e0 - 1.0);
    momentum.add((sim.momentum() - p0).norm() / p0.norm());
    gap.add(std::min(0.0, sim.min_gap()));
  }
  char what[160];
  std::snprintf(what, sizeof what, "relative drift of Sum mv^2/2 (recomputed), %llu collisions, eta 0.65, %s calendar",
                static_cast<unsigned long long>(collisions), calendar);
  rows.push_back(bound_row("energy_drift", what, energy, 1e-9));
  rows.push_back(bound_row("energy_book_drift", "relative drift of the incremental energy book, same runs", book, 1e-9));
  rows.push_back(bound_row("momentum_drift", "|P - P0|/|P0|, same runs (stream U = 0.03)", momentum, 1e-9));
  rows.push_back(bound_row("overlap", "-min(0, smallest gap) at the end, same runs", gap, 1e-10));
}

// ---- 4: velocity distribution -------------------------------------------------------------

void velocity_distribution(const Options& o, std::vector<Row>& rows) {
  const double eta = 0.65, kT = 0.02;
  const int snapshots = o.quick ? 80 : 400;
  const double eq_coll = 100.0;  // from kurtosis 1.5 to 3 takes a few collisions per disk
  const double tau_est = tau_from_z(henderson_z(eta), kT);
  Sample kurt, sixth, equip, kt_dev, kurt0;
  for (int s = 0; s < o.seeds; ++s) {
    const ed::Config c = box(o.n, eta, kT, 9000 + s);
    // Fluid positions: the lattice start melted for 50 collisions per disk.
    std::vector<ed::DiskInit> disks;
    {
      ed::Simulation melt(c);
      melt.run_until(50.0 * tau_est);
      for (const auto& m : disk_states(melt)) {
        ed::DiskInit d;
        d.r = {m.x, m.y};
        disks.push_back(d);
      }
    }
    // Every disk at the same speed in a random direction, then zero total momentum and
    // Σ m v²/2 = N kT exactly (m = 1): far from Maxwell (one component's kurtosis 1.5).
    grainflow::core::Rng rng(9000 + s);
    double px = 0.0, py = 0.0;
    for (auto& d : disks) {
      const double a = 2.0 * kPi * rng.uniform(), speed = std::sqrt(2.0 * kT);
      d.v = {speed * std::cos(a), speed * std::sin(a)};
      px += d.v.x();
      py += d.v.y();
    }
    const double n = disks.size();
    double k = 0.0;
    for (auto& d : disks) {
      d.v = {d.v.x() - px / n, d.v.y() - py / n};
      k += 0.5 * d.v.squaredNorm();
    }
    const double scale = std::sqrt(n * kT / k);
    for (auto& d : disks) d.v = d.v * scale;
    ed::Simulation sim(c, disks);
    auto moments = [&](double& m2x, double& m2y, double& m4, double& m6) {
      for (const auto& v : disk_states(sim)) {
        m2x += v.vx * v.vx;
        m2y += v.vy * v.vy;
        for (double u : {v.vx, v.vy}) {
          const double u2 = u * u;
          m4 += u2 * u2;
          m6 += u2 * u2 * u2;
        }
      }
    };
    {
      double m2x = 0, m2y = 0, m4 = 0, m6 = 0;
      moments(m2x, m2y, m4, m6);
      kurt0.add(2.0 * n * m4 / ((m2x + m2y) * (m2x + m2y)));
    }
    sim.run_until(eq_coll * tau_est);
    sim.reset_measurements();
    double m2x = 0, m2y = 0, m4 = 0, m6 = 0;
    for (int k2 = 1; k2 <= snapshots; ++k2) {
      sim.run_until(eq_coll * tau_est + k2 * tau_est);  // one mean free time apart
      moments(m2x, m2y, m4, m6);
    }
    const double samples = 2.0 * n * snapshots, m2 = (m2x + m2y) / samples;
    kurt.add(m4 / samples / (m2 * m2));
    sixth.add(m6 / samples / (m2 * m2 * m2));
    equip.add(m2x / m2y);
    kt_dev.add(sim.observables().kT / kT - 1.0);
  }
  const double dof = 2.0 * (o.n - 1);  // velocity components left free by E and P fixed
  char what[160];
  std::snprintf(what, sizeof what, "kurtosis of v_x at the start (every disk at one speed)");
  rows.push_back(stat_row("kurtosis_start", what, kurt0, {{"equal_speeds", 1.5}}));
  std::snprintf(what, sizeof what, "<v_x^4>/<v_x^2>^2, eta 0.65, %d snapshots 1 tau apart after %g coll/disk",
                snapshots, eq_coll);
  rows.push_back(stat_row("kurtosis", what, kurt, {{"Maxwell", 3.0}, {"MaxwellNVE", 3.0 * dof / (dof + 2.0)}}));
  rows.push_back(stat_row("sixth_moment", "<v_x^6>/<v_x^2>^3, same snapshots", sixth,
                          {{"Maxwell", 15.0}, {"MaxwellNVE", 15.0 * dof * dof / ((dof + 2.0) * (dof + 4.0))}}));
  rows.push_back(stat_row("equipartition", "<v_x^2>/<v_y^2>, same snapshots", equip, {{"exact", 1.0}}));
  rows.push_back(bound_row("kT_deviation", "time-averaged kT / set kT - 1 over the sampling windows", kt_dev, 1e-9));
}

// ---- output and comparison -----------------------------------------------------------------

void print(const std::vector<Row>& rows) {
  std::printf("%-20s %13s %11s %8s  %s\n", "# key", "value", "std.err", "rel.se", "references: value (dev %, dev/se)");
  for (const auto& r : rows) {
    if (r.bound > 0.0) {
      std::printf("%-20s %13.4g %11s %8s  max |.| over runs, bound %.0e: %s   # %s\n", r.key.c_str(), r.mean, "-",
                  "-", r.bound, r.mean <= r.bound ? "ok" : "EXCEEDED", r.what.c_str());
      continue;
    }
    std::printf("%-20s %13.6f %11.6f %7.3f%%  ", r.key.c_str(), r.mean, r.se, 100.0 * r.se / std::abs(r.mean));
    for (const auto& [name, ref] : r.refs) {
      if (ref != 0.0)
        std::printf("%s %.5f (%+.2f %%, %+.1f se)  ", name.c_str(), ref, 100.0 * (r.mean / ref - 1.0),
                    (r.mean - ref) / r.se);
      else
        std::printf("%s %.5f (%+.1f se)  ", name.c_str(), ref, (r.mean - ref) / r.se);
    }
    std::printf("  # %s\n", r.what.c_str());
  }
}

// Rows of an earlier output: key → (value, std.err or NaN for bound rows).
std::map<std::string, std::pair<double, double>> read_rows(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw grainflow::Error("ed_physics_check: cannot read " + path);
  std::map<std::string, std::pair<double, double>> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string key, value, se;
    if (!(s >> key >> value >> se)) continue;
    try {
      out[key] = {std::stod(value), se == "-" ? NAN : std::stod(se)};
    } catch (const std::exception&) {
      // not a table row
    }
  }
  return out;
}

int compare(const std::vector<Row>& rows, const std::string& path) {
  const auto old = read_rows(path);
  std::printf("\n# comparison with %s: z = (this - that)/sqrt(se^2 + se'^2); |z| > 3 flagged\n", path.c_str());
  std::printf("%-20s %13s %13s %9s  %s\n", "# key", "this", "that", "z", "verdict");
  int flagged = 0;
  for (const auto& r : rows) {
    const auto it = old.find(r.key);
    if (it == old.end()) {
      std::printf("%-20s %13.6g %13s %9s  missing there\n", r.key.c_str(), r.mean, "-", "-");
      continue;
    }
    const auto [v, se] = it->second;
    if (r.bound > 0.0) {
      const bool ok = r.mean <= r.bound && v <= r.bound;
      flagged += !ok;
      std::printf("%-20s %13.4g %13.4g %9s  %s\n", r.key.c_str(), r.mean, v, "-", ok ? "both within bound" : "BOUND");
      continue;
    }
    const double z = (r.mean - v) / std::sqrt(r.se * r.se + se * se);
    if (std::isnan(z)) {  // a single run has no error bar
      std::printf("%-20s %13.6f %13.6f %9s  no error bar\n", r.key.c_str(), r.mean, v, "-");
      continue;
    }
    const bool ok = std::abs(z) <= 3.0;
    flagged += !ok;
    std::printf("%-20s %13.6f %13.6f %+9.2f  %s\n", r.key.c_str(), r.mean, v, z, ok ? "ok" : "DIFFERENT");
  }
  std::printf("# %d row(s) flagged\n", flagged);
  return flagged ? 2 : 0;
}

int usage(const char* why) {
  std::fprintf(stderr, "ed_physics_check: %s\nusage: ed_physics_check [--quick] [--seeds K>=1] [--n N>=100] [--compare FILE]\n",
               why);
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--quick") {
      o.quick = true;
      o.seeds = 3;
    } else if (a == "--seeds" && has_value) {
      o.seeds = std::atoi(argv[++i]);
      if (o.seeds < 1) return usage("--seeds must be a positive integer");
    } else if (a == "--n" && has_value) {
      o.n = std::atoi(argv[++i]);
      if (o.n < 100) return usage("--n must be an integer >= 100");
    } else if (a == "--compare" && has_value) {
      o.compare = argv[++i];
    } else {
      return usage(("unknown or incomplete option '" + a + "'").c_str());
    }
  }
  try {
    std::printf("# ED engine physics check: N = %d disks per box, %d independent runs (seeds) per row%s;\n", o.n,
                o.seeds, o.quick ? ", QUICK (1/5 lengths)" : "");
    std::printf("# value = mean over the runs, std.err = their standard deviation / sqrt(runs)\n");
    std::vector<Row> rows;
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    auto lap = [&, t = t0](const char* what) mutable {
      const auto now = clock::now();
      std::fprintf(stderr, "%-22s %7.1f s\n", what, std::chrono::duration<double>(now - t).count());
      t = now;
    };
    equation_of_state(o, rows);
    lap("equation of state");
    mean_free_time(o, rows);
    lap("mean free time");
    conservation(o, rows);
    lap("conservation");
    velocity_distribution(o, rows);
    lap("velocity distribution");
    std::fprintf(stderr, "%-22s %7.1f s\n", "total", std::chrono::duration<double>(clock::now() - t0).count());
    print(rows);
    if (!o.compare.empty()) return compare(rows, o.compare);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ed_physics_check: %s\n", e.what());
    return 1;
  }
  return 0;
}
