// Contact sub-models of the DEM engine against hand-computed values: Walton's latching
// spring (seed 000 Eq. 2.1–2.9), Walton's tangential model (Eq. 2.10–2.14), the LAMMPS
// gran/hooke/history law, van der Waals cohesion (Eq. 5.28, 5.21, 5.29); and the tables
// of sub-models: names, checks, mixing, composition and time scales (§2.5).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>

#include "engine/core/error.hpp"
#include "engine/dem/contact_law.hpp"
#include "engine/dem/time_step.hpp"
#include "engine/dem/vdw_cohesion.hpp"

using namespace grainflow::dem;
using grainflow::Error;

namespace {

std::unique_ptr<ContactLaw> law_of(const ContactModelSpec& spec, const ContactParams& p, double meff = 1.0) {
  std::array<ContactParams, 9> per;
  per.fill(p);
  std::array<double, 9> m;
  m.fill(meff);
  return make_contact_law(spec, per, m);
}

ContactKinematics kin(double delta, double nx = 1, double ny = 0, double nz = 0) {
  ContactKinematics k{};
  k.n[0] = nx;
  k.n[1] = ny;
  k.n[2] = nz;
  k.delta = delta;
  k.m_eff = 1.0;
  k.r_eff = 1.0;
  k.dt = 1.0;
  return k;
}

}  // namespace

TEST(WaltonNormal, LoadUnloadReloadCycleMatchesHandValues) {
  ContactParams p;
  p.k1 = 100.0;
  p.e = 0.5;  // K2 = K1/e² = 400, α0 = α_max (1 − K1/K2) = 0.75 α_max
  auto law = law_of({NormalKind::Walton, TangentialKind::None, CohesionKind::None}, p);
  std::vector<double> h(law->history_size(), 0.0);
  ASSERT_EQ(law->history_size(), 1);
  struct Step {
    double alpha, force;
  };
  const Step steps[] = {
      {1.0e-3, 0.100},   // loading K1 α
      {2.0e-3, 0.200},   // loading, α_max = 2e-3 → α0 = 1.5e-3
      {1.8e-3, 0.120},   // unloading K2 (α − α0) = 400 × 0.3e-3
      {1.9e-3, 0.160},   // reloading along the unloading line
      {1.6e-3, 0.040},   // unloading
      {1.4e-3, 0.000},   // below α0: latched, zero force
      {2.5e-3, 0.250},   // past α_max: back on K1 α, α0 = 1.875e-3
      {2.4e-3, 0.210},   // unloading from the new maximum: 400 × (2.4 − 1.875)e-3
  };
  for (const Step& s : steps) {
    ContactForce out;
    ASSERT_TRUE(law->evaluate(0, kin(s.alpha), h.data(), true, out));
    EXPECT_NEAR(-out.f[0], s.force, 1e-12) << "alpha = " << s.alpha;
    EXPECT_EQ(out.f[1], 0.0);
  }
  EXPECT_NEAR(h[0], 1.875e-3, 1e-15);
  // Separation clears the history.
  ContactForce out;
  EXPECT_FALSE(law->evaluate(0, kin(-1e-6), h.data(), true, out));
  EXPECT_EQ(h[0], 0.0);
}

TEST(WaltonNormal, GivenK2ReplacesTheRestitution) {
  ContactParams p;
  p.k1 = 100.0;
  p.e = 0.3;     // not used: K2 is given
  p.k2 = 400.0;  // e = sqrt(K1/K2) = 0.5, as the hand values above
  auto law = law_of({NormalKind::Walton, TangentialKind::None, CohesionKind::None}, p);
  std::vector<double> h(law->history_size(), 0.0);
  ContactForce out;
  law->evaluate(0, kin(2.0e-3), h.data(), true, out);
  law->evaluate(0, kin(1.8e-3), h.data(), true, out);
  EXPECT_NEAR(-out.f[0], 0.120, 1e-12);
  EXPECT_NEAR(h[0], 1.5e-3, 1e-15);
  p.k2 = 50.0;  // softer than K1: e > 1
  EXPECT_THROW(validate(p, {NormalKind::Walton, TangentialKind::None, CohesionKind::None}, "g"), Error);
}

TEST(WaltonNormal, ElasticWhenRestitutionIsOne) {
  ContactParams p;
  p.k1 = 50.0;
  p.e = 1.0;
  auto law = law_of({NormalKind::Walton, TangentialKind::None, CohesionKind::None}, p);
  std::vector<double> h(1, 0.0);
  ContactForce out;
  law->evaluate(0, kin(2e-3), h.data(), true, out);
  law->evaluate(0, kin(1e-3), h.data(), true, out);
  EXPECT_DOUBLE_EQ(-out.f[0], 50.0 * 1e-3);
}

namespace {
// Walton tangential with F_N = 1 N (K1 = 1000 N/m at α = 1 mm, e = 1), K0 = 1000 N/m,
// μ = 0.5, γ = 1: K_T = K0 (1 − (T − T*)/(μF_N − T*)) on loading.
struct WaltonTangentialFixture : ::testing::Test {
  ContactParams p;
  std::unique_ptr<ContactLaw> law;
  std::vector<double> h;
  void SetUp() override {
    p.k1 = 1000.0;
    p.e = 1.0;
    p.kt = 1000.0;
    p.mu = 0.5;
    p.walton_gamma = 1.0;
    law = law_of({NormalKind::Walton, TangentialKind::Walton, CohesionKind::None}, p);
    h.assign(law->history_size(), 0.0);
  }
  // Tangential slip of i relative to j of −ds along y in one step (dt = 1): loads +ds.
  ContactForce push(double ds, double nx = 1, double ny = 0) {
    ContactKinematics k = kin(1e-3, nx, ny);
    k.vt[1] = -ds;
    if (ny != 0.0) {  // keep v_t tangential for a rotated normal
      const double d = k.vt[0] * nx + k.vt[1] * ny;
      k.vt[0] -= d * nx;
      k.vt[1] -= d * ny;
    }
    ContactForce out;
    EXPECT_TRUE(law->evaluate(0, k, h.data(), true, out));
    return out;
  }
};
}  // namespace

TEST_F(WaltonTangentialFixture, StickFollowsEq210LoadingBranch) {
  EXPECT_EQ(law->history_size(), 1 + 6);
  EXPECT_NEAR(push(1e-4).f[1], 0.100, 1e-12);  // K_T = K0
  EXPECT_NEAR(push(1e-4).f[1], 0.180, 1e-12);  // K_T = K0 (1 − 0.1/0.5) = 800
  EXPECT_NEAR(push(1e-4).f[1], 0.244, 1e-12);  // K_T = 640
}

TEST_F(WaltonTangentialFixture, SlipCapsAtMuFn) {
  const ContactForce out = push(1e-3);  // K0 Δs = 1 N > μ F_N = 0.5 N
  EXPECT_NEAR(out.f[1], 0.5, 1e-12);
  EXPECT_NEAR(push(1e-3).f[1], 0.5, 1e-12);
  // Normal part unchanged: −F_N along n.
  EXPECT_NEAR(out.f[0], -1.0, 1e-12);
}

TEST_F(WaltonTangentialFixture, ReversalSetsTStarAndUsesUnloadingBranch) {
  push(1e-4);
  push(1e-4);
  push(1e-4);  // T = 0.244
  // Reversal: T* = 0.244; K_T = K0 (1 − (T* − T)/(μF_N + T*)) = K0 at T = T*.
  EXPECT_NEAR(push(-1e-4).f[1], 0.144, 1e-12);
  // Next: K_T = 1000 (1 − 0.1/0.744) → T = 0.144 − 0.1 (1 − 0.1/0.744).
  EXPECT_NEAR(push(-1e-4).f[1], 0.144 - 0.1 * (1.0 - 0.1 / 0.744), 1e-12);
  EXPECT_NEAR(h[1 + 3], 0.244, 1e-12);  // T* in history
}

TEST_F(WaltonTangentialFixture, ContactPlaneRotationKeepsMagnitude) {
  push(2e-4);  // T = 0.2 along +y, n = +x
  const double th = 0.3;
  const double nx = std::cos(th), ny = std::sin(th);
  const ContactForce out = push(0.0, nx, ny);
  // Tangential part = f + F_N n (normal part of the force on i is −F_N n).
  const double t0 = out.f[0] + nx, t1 = out.f[1] + ny;
  EXPECT_NEAR(std::hypot(t0, t1), 0.2, 1e-12);  // Eq. 2.11 keeps |T|
  EXPECT_NEAR(t0 * nx + t1 * ny, 0.0, 1e-12);   // in the new tangent plane
  EXPECT_GT(t1, 0.0);
}

TEST_F(WaltonTangentialFixture, PerpendicularDisplacementSeesK0) {
  push(1e-4);  // T = 0.1 along +y
  ContactKinematics k = kin(1e-3);
  k.vt[2] = -1e-4;  // displacement along +z, perpendicular to the old force
  ContactForce out;
  law->evaluate(0, k, h.data(), true, out);
  EXPECT_NEAR(out.f[1], 0.1, 1e-12);
  EXPECT_NEAR(out.f[2], 0.1, 1e-12);  // K0 Δs_⊥
}

TEST(HookeHistory, MatchesLammpsFormulas) {
  ContactParams p;
  p.k1 = 100.0;
  p.e = 0.9;
  p.kt = 200.0 / 7.0;
  p.mu = 0.5;
  const double meff = 6.544984694978735e-07;  // two 1 mm spheres of 2500 kg/m³
  const double gn = hooke_gamma_from_restitution(p.k1, p.e, meff);
  EXPECT_NEAR(gn, 828.628, 0.01);  // the value in the reference inputs
  auto law = law_of({NormalKind::Hooke, TangentialKind::History, CohesionKind::None}, p, meff);
  EXPECT_EQ(law->history_size(), 3);
  std::vector<double> h(3, 0.0);
  ContactKinematics k = kin(1e-5);
  k.m_eff = meff;
  k.dt = 5e-6;
  k.vn = 0.1;
  k.vt[1] = 0.01;
  ContactForce out;
  law->evaluate(0, k, h.data(), true, out);
  const double fn = 100.0 * 1e-5 + meff * gn * 0.1;
  EXPECT_NEAR(-out.f[0], fn, 1e-15);
  const double shear = 0.01 * 5e-6;
  const double fs = -(p.kt * shear + meff * 0.5 * gn * 0.01);
  EXPECT_NEAR(out.f[1], fs, 1e-15);
  EXPECT_NEAR(h[1], shear, 1e-20);
  // Sliding: history rescaled so that kt·s + m γt v_t equals the cap (LAMMPS rule).
  k.vt[1] = 10.0;
  law->evaluate(0, k, h.data(), true, out);
  const double fn2 = 100.0 * 1e-5 + meff * gn * 0.1;
  EXPECT_NEAR(std::fabs(out.f[1]), 0.5 * fn2, 1e-14);
  EXPECT_NEAR(std::fabs(p.kt * h[1] + meff * 0.5 * gn * 10.0), 0.5 * fn2, 1e-14);
}

TEST(VanDerWaals, PairAndWallForcesFollowEq529) {
  ContactParams p;
  p.k1 = 1e-7;
  p.e = 0.95;
  p.hamaker = 1e-18;
  p.r_ss = 3e-10;
  p.alpha_min = 4e-10;
  p.alpha_cut = 1e-6;
  const double R = 3.175e-5;
  auto law = law_of({NormalKind::Walton, TangentialKind::None, CohesionKind::VanDerWaals}, p);
  EXPECT_DOUBLE_EQ(law->cohesion_range(), 1e-6);
  std::vector<double> h(1, 0.0);
  const double rss6 = std::pow(3e-10, 6);
  for (double a : {5e-10, 1e-9, 1e-8, 1e-7, 9e-7}) {
    ContactKinematics k = kin(-a);
    k.r_eff = 0.5 * R;  // equal spheres
    ContactForce out;
    ASSERT_TRUE(law->evaluate(0, k, h.data(), true, out));
    const double eq528 = 1e-18 * R / (12 * a * a) * (1 - rss6 / (60 * std::pow(a, 6)));
    EXPECT_NEAR(out.f[0], eq528, 1e-12 * eq528) << a;  // attraction: towards j (+n)
    k.wall = true;
    k.r_eff = R;
    law->evaluate(0, k, h.data(), true, out);
    const double eq521 = 1e-18 * R / (6 * a * a) * (1 - rss6 / (60 * std::pow(a, 6)));
    EXPECT_NEAR(out.f[0], eq521, 1e-12 * eq521) << a;
  }
  // Eq. 5.29: zero at and below α_min — in the gap and during overlap, where only the
  // spring acts (the pull of α_min is not held: it would keep a slow pair on the lossless
  // K2 line of the latching spring for ever, vdw_cohesion.hpp).
  ContactKinematics k = kin(-1e-10);
  k.r_eff = 0.5 * R;
  ContactForce out;
  EXPECT_FALSE(law->evaluate(0, k, h.data(), true, out));
  k.delta = -4e-10;
  EXPECT_FALSE(law->evaluate(0, k, h.data(), true, out));
  k.delta = 1e-9;
  ASSERT_TRUE(law->evaluate(0, k, h.data(), true, out));
  EXPECT_NEAR(out.f[0], -1e-7 * 1e-9, 1e-30);  // the spring's K1·α alone, repulsive (−n)
  // Zero beyond the cutoff.
  k.delta = -1.1e-6;
  EXPECT_FALSE(law->evaluate(0, k, h.data(), true, out));
}

TEST(TimeStep, Eq223) {
  const double m = 5026.0, k1 = 1e-7, e = 0.95;
  EXPECT_DOUBLE_EQ(walton_time_step(m, k1, e, 50), std::numbers::pi * e * std::sqrt(m / (2 * k1)) / 50);
  EXPECT_DOUBLE_EQ(walton_collision_time(m / 2, k1, e), std::numbers::pi * std::sqrt(m / 2 / (k1 / (e * e))));
}

// ---- the sub-model tables (contact_models.hpp)

namespace {

template <class Kind>
void expect_names_round_trip() {
  const auto rows = sub_models<Kind>();
  const std::vector<std::string> names = model_names<Kind>();
  ASSERT_EQ(rows.size(), Kind::Models::size);
  ASSERT_EQ(names.size(), rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    EXPECT_EQ(names[r], rows[r].name);
    EXPECT_FALSE(rows[r].description.empty()) << names[r];
    const Kind k = kind_from_name<Kind>(names[r]);
    EXPECT_EQ(k.row, static_cast<int>(r)) << names[r];
    EXPECT_EQ(model_name(k), names[r]);
  }
}

template <class Kind>
std::string error_of_name(const std::string& name) {
  try {
    kind_from_name<Kind>(name);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "\"" << name << "\" was accepted";
  return {};
}

template <class Kind>
void expect_unknown_name_lists_allowed(const std::string& bad) {
  const std::string msg = error_of_name<Kind>(bad);
  EXPECT_NE(msg.find(std::string(Kind::kFamily) + " \"" + bad + "\" is unknown"), std::string::npos) << msg;
  for (const std::string& name : model_names<Kind>()) EXPECT_NE(msg.find(name), std::string::npos) << msg;
}

// Coefficients every row accepts.
ContactParams valid_params() {
  ContactParams p;
  p.k1 = 100.0;
  p.e = 0.9;
  p.kt = 200.0 / 7.0;
  p.mu = 0.5;
  p.hamaker = 1e-19;
  p.r_ss = 3e-10;
  p.alpha_min = 4e-10;
  p.alpha_cut = 1e-7;
  return p;
}

// Test-only sub-model that refuses Walton's normal model.
struct RefusesWalton {
  static constexpr std::string_view kName = "refuses_walton";
  template <class Other>
  static constexpr bool kCombinesWith = !std::is_same_v<Other, WaltonNormal>;
};

}  // namespace

TEST(SubModelTables, NamesRoundTripThroughFromName) {
  expect_names_round_trip<NormalKind>();
  expect_names_round_trip<TangentialKind>();
  expect_names_round_trip<CohesionKind>();
  EXPECT_EQ(normal_model_names(), model_names<NormalKind>());
  EXPECT_EQ(tangential_model_names(), model_names<TangentialKind>());
  EXPECT_EQ(cohesion_model_names(), model_names<CohesionKind>());
  // Scene files use these names; checkpoints store these rows.
  EXPECT_EQ(normal_kind_from_name("walton"), NormalKind::Walton);
  EXPECT_EQ(normal_kind_from_name("hooke"), NormalKind::Hooke);
  EXPECT_EQ(tangential_kind_from_name("walton"), TangentialKind::Walton);
  EXPECT_EQ(tangential_kind_from_name("history"), TangentialKind::History);
  EXPECT_EQ(tangential_kind_from_name("none"), TangentialKind::None);
  EXPECT_EQ(cohesion_kind_from_name("none"), CohesionKind::None);
  EXPECT_EQ(cohesion_kind_from_name("vdw"), CohesionKind::VanDerWaals);
  EXPECT_EQ(NormalKind::Hooke.row, 1);
  EXPECT_EQ(TangentialKind::None.row, 2);
  EXPECT_EQ(CohesionKind::VanDerWaals.row, 1);
}

TEST(SubModelTables, UnknownNameListsTheAllowedOnes) {
  expect_unknown_name_lists_allowed<NormalKind>("hertz");
  expect_unknown_name_lists_allowed<TangentialKind>("mindlin");
  expect_unknown_name_lists_allowed<CohesionKind>("jkr");
  EXPECT_EQ(error_of_name<NormalKind>("hertz"), "dem: normal contact model \"hertz\" is unknown; allowed: walton, hooke");
  EXPECT_THROW(normal_kind_from_name(""), Error);
  EXPECT_THROW(normal_kind_from_name("Walton"), Error);  // names are exact
  // A row outside the table (a corrupt checkpoint) is refused, not dispatched.
  ContactModelSpec bad;
  bad.tangential = TangentialKind{7};
  try {
    validate(valid_params(), bad, "groups[0].contact");
    ADD_FAILURE() << "row 7 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("tangential contact model number 7 is unknown"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_contact_law(bad, {}, {}), Error);
}

TEST(SubModelTables, EveryCompositionValidatesAndBuildsItsLaw) {
  const ContactParams p = valid_params();
  int laws = 0;
  for (const std::string& n : normal_model_names())
    for (const std::string& t : tangential_model_names())
      for (const std::string& c : cohesion_model_names()) {
        const ContactModelSpec spec{normal_kind_from_name(n), tangential_kind_from_name(t), cohesion_kind_from_name(c)};
        EXPECT_NO_THROW(validate(p, spec, "p")) << n << " " << t << " " << c;
        const int history = visit_model(spec.normal, [&]<class N>(std::type_identity<N>) {
          return visit_model(spec.tangential, [&]<class T>(std::type_identity<T>) {
            return visit_model(spec.cohesion,
                               [&]<class C>(std::type_identity<C>) { return N::kHistory + T::kHistory + C::kHistory; });
          });
        });
        EXPECT_EQ(law_of(spec, p)->history_size(), history) << n << " " << t << " " << c;
        ++laws;
      }
  EXPECT_EQ(laws, int(NormalModels::size * TangentialModels::size * CohesionModels::size));
}

TEST(SubModelTables, ACompositionASubModelRefusesIsNotComposable) {
  static_assert(!combinable<WaltonNormal, RefusesWalton>() && !combinable<RefusesWalton, WaltonNormal>());
  static_assert(combinable<HookeNormal, RefusesWalton>());
  static_assert(!kComposable<WaltonNormal, RefusesWalton, NoCohesion>);
  static_assert(kComposable<HookeNormal, RefusesWalton, NoCohesion>);
  static_assert(kComposable<WaltonNormal, HistoryTangential, VdwCohesion>);
}

TEST(SubModelTables, EachRowChecksWhatItReads) {
  const auto error_of = [](const ContactParams& p, const ContactModelSpec& spec) -> std::string {
    try {
      validate(p, spec, "groups[1].contact");
    } catch (const Error& e) {
      return e.what();
    }
    return {};
  };
  const ContactModelSpec walton{NormalKind::Walton, TangentialKind::Walton, CohesionKind::None};
  ContactParams p = valid_params();
  p.walton_gamma = 0.0;
  EXPECT_EQ(error_of(p, walton),
            "dem: groups[1].contact.walton_gamma = 0 is not allowed; the exponent γ of Eq. 2.10 must be in (0, 10]");
  EXPECT_EQ(error_of(p, {NormalKind::Walton, TangentialKind::History, CohesionKind::None}), "");  // not read
  p = valid_params();
  p.e = 2.0;
  EXPECT_NE(error_of(p, walton).find("groups[1].contact.e = 2"), std::string::npos);
  p.gamma_n = 500.0;  // Hooke with a given γn does not read e
  EXPECT_EQ(error_of(p, {NormalKind::Hooke, TangentialKind::History, CohesionKind::None}), "");
  p = valid_params();
  p.alpha_cut = p.alpha_min;
  EXPECT_EQ(error_of(p, walton), "");
  EXPECT_NE(error_of(p, {NormalKind::Walton, TangentialKind::None, CohesionKind::VanDerWaals}).find("alpha_cut"),
            std::string::npos);
  p = valid_params();
  p.kt = 0.0;  // frictionless contacts need no tangential spring
  EXPECT_EQ(error_of(p, {NormalKind::Hooke, TangentialKind::None, CohesionKind::None}), "");
  EXPECT_NE(error_of(p, {NormalKind::Hooke, TangentialKind::History, CohesionKind::None}).find(".kt = 0"),
            std::string::npos);
}

TEST(SubModelTables, MixTakesEachBlocksArithmeticMeans) {
  ContactParams a, b;
  a.k1 = 100.0, b.k1 = 300.0;
  a.e = 0.5, b.e = 0.9;
  a.gamma_n = 10.0, b.gamma_n = 30.0;
  a.kt = 20.0, b.kt = 40.0;
  a.mu = 0.2, b.mu = 0.6;
  a.walton_gamma = 1.0, b.walton_gamma = 0.5;
  a.gamma_t = -1.0, b.gamma_t = 8.0;
  a.damp_flag = true, b.damp_flag = false;
  a.hamaker = 1e-19, b.hamaker = 3e-19;
  a.vdw_radius = 0.0, b.vdw_radius = 2e-6;
  a.r_ss = 2e-10, b.r_ss = 4e-10;
  a.alpha_min = 4e-10, b.alpha_min = 6e-10;
  a.alpha_cut = 1e-7, b.alpha_cut = 3e-7;
  const ContactParams c = mix(a, b);
  EXPECT_EQ(c.k1, 200.0);
  EXPECT_EQ(c.e, 0.5 * (0.5 + 0.9));
  EXPECT_EQ(c.gamma_n, 20.0);
  EXPECT_EQ(c.kt, 30.0);
  EXPECT_EQ(c.mu, 0.5 * (0.2 + 0.6));
  EXPECT_EQ(c.walton_gamma, 0.75);
  EXPECT_EQ(c.gamma_t, -1.0);  // derived unless both groups give it
  EXPECT_FALSE(c.damp_flag);
  EXPECT_EQ(c.hamaker, 0.5 * (1e-19 + 3e-19));
  EXPECT_EQ(c.vdw_radius, 1e-6);
  EXPECT_EQ(c.r_ss, 0.5 * (2e-10 + 4e-10));
  EXPECT_EQ(c.alpha_min, 0.5 * (4e-10 + 6e-10));
  EXPECT_EQ(c.alpha_cut, 0.5 * (1e-7 + 3e-7));
}

TEST(SubModelTimeScales, WaltonCollisionTimeIsEq222) {
  ContactParams p = valid_params();
  p.k1 = 1e-7;
  p.e = 0.95;
  const double mu = 5026.0 / 2;
  const ContactModelSpec spec{NormalKind::Walton, TangentialKind::None, CohesionKind::None};
  EXPECT_DOUBLE_EQ(collision_time(spec, p, mu, mu), std::numbers::pi * 0.95 * std::sqrt(mu / 1e-7));
  EXPECT_EQ(collision_time(spec, p, mu, mu), walton_collision_time(mu, p.k1, p.e));
  // The stiffest spring is the unloading one, K2 = K1/e² (Eq. 2.9).
  EXPECT_DOUBLE_EQ(stability_limit(spec, p, mu), 2.0 * std::sqrt(mu / (1e-7 / (0.95 * 0.95))));
  // A tangential spring stiffer than that sets the limit on 2/7 of the reduced mass.
  p.kt = 1e-5;
  EXPECT_DOUBLE_EQ(stability_limit({NormalKind::Walton, TangentialKind::Walton, CohesionKind::None}, p, mu),
                   2.0 * std::sqrt(2.0 / 7.0 * mu / 1e-5));
}

TEST(SubModelTimeScales, HookeCollisionTimeIsPiOverOmegaD) {
  ContactParams p = valid_params();
  const ContactModelSpec spec{NormalKind::Hooke, TangentialKind::None, CohesionKind::None};
  const double mu = 6.544984694978735e-07;  // two 1 mm spheres of 2500 kg/m³
  p.gamma_n = 500.0;
  EXPECT_DOUBLE_EQ(collision_time(spec, p, mu, mu), std::numbers::pi / std::sqrt(100.0 / mu - 0.25 * 500.0 * 500.0));
  // γn derived from e: a collision of that reduced mass rebounds with e, v ∝ exp(−γn t/2).
  p.gamma_n = -1.0;
  const double gn = hooke_gamma_from_restitution(p.k1, p.e, mu);
  const double tc = collision_time(spec, p, mu, mu);
  EXPECT_DOUBLE_EQ(tc, std::numbers::pi / std::sqrt(100.0 / mu - 0.25 * gn * gn));
  EXPECT_NEAR(std::exp(-0.5 * gn * tc), p.e, 1e-12);
  // A wall (reduced mass m = 2 μ) with γn derived for two equal particles (m_eff = μ).
  EXPECT_DOUBLE_EQ(collision_time(spec, p, 2 * mu, mu), std::numbers::pi / std::sqrt(100.0 / (2 * mu) - 0.25 * gn * gn));
  // Overdamped: no rebound, no collision time.
  p.gamma_n = 1e9;
  EXPECT_EQ(collision_time(spec, p, mu, mu), 0.0);
  EXPECT_DOUBLE_EQ(stability_limit(spec, p, mu), 2.0 * std::sqrt(mu / 100.0));
}
