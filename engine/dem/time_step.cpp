#include "engine/dem/time_step.hpp"

#include <algorithm>
#include <cmath>

namespace grainflow::dem {

double leapfrog_stability_limit(double mu_red, double k) { return 2.0 * std::sqrt(mu_red / k); }

double collision_time(const ContactModelSpec& spec, const ContactParams& p, double mu_red, double m_eff_pair) {
  return visit_model(spec.normal,
                     [&]<class N>(std::type_identity<N>) { return N::collision_time(p, mu_red, m_eff_pair); });
}

double stability_limit(const ContactModelSpec& spec, const ContactParams& p, double mu_red) {
  const double kn = visit_model(spec.normal, [&]<class N>(std::type_identity<N>) { return N::max_stiffness(p); });
  const double kt = visit_model(spec.tangential, [&]<class T>(std::type_identity<T>) { return T::stiffness(p); });
  const double lim = leapfrog_stability_limit(mu_red, kn);
  return kt > 0.0 ? std::min(lim, leapfrog_stability_limit(2.0 / 7.0 * mu_red, kt)) : lim;  // 0: no spring
}

}  // namespace grainflow::dem
