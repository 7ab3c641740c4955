// The geometry and relative motion of one contact (particle–particle or particle–wall),
// the common input of every contact sub-model (seed 000 §2.4). SI units.
#pragma once

namespace grainflow::dem {

struct ContactKinematics {
  double n[3];     // unit normal from particle i towards its partner (j or the wall)
  double delta;    // overlap R_i + R_j − r [m]; > 0 when touching, −delta = surface gap
  double vn;       // approach speed (v_i − v_j)·n [m/s]; > 0 when closing
  double vt[3];    // tangential velocity of i's surface relative to the partner's at the
                   // contact point [m/s]: (v_i − v_j)_t + (R_i ω_i + R_j ω_j) × n
  double m_eff;    // reduced mass [kg] (m_i for a wall)
  double r_eff;    // R_i R_j/(R_i + R_j) (R_i for a wall) [m], for cohesion
  double dt;       // time step [s]
  bool wall;       // partner is a flat wall
};

// Result of one contact evaluation: force on particle i and the lever vector for torques.
struct ContactForce {
  double f[3];     // force on i [N]; the partner gets −f
  double c[3];     // n × F_t [N]; torque on i is R_i·c, on j also R_j·c
};

}  // namespace grainflow::dem
