// The temperature of the disks meeting an open-stream boundary (the dispenser piston, the
// outlet filter; seed 003 §3.3), for streams that cool on their way (inelastic disks, ch. 5):
// a running mean of m(v_y − <v_y>)² over the last `window` disks. v_y is not biased by the
// flux weight of who meets a plane normal to x (that weight depends on v_x only).
#pragma once
#include <algorithm>
#include <cmath>

namespace grainflow::ed {

class ArrivalTemperature {
public:
  ArrivalTemperature() = default;
  // Starts at kT (the stream's) with mean v_y = 0; window ≥ 1 disks.
  ArrivalTemperature(double kT, double mass, double window)
      : m_(mass), w_(1.0 / window), mean_vy2_(kT / mass) {}
  void observe(double vy) {
    mean_vy_ += w_ * (vy - mean_vy_);
    mean_vy2_ += w_ * (vy * vy - mean_vy2_);
  }
  double kT() const { return m_ * std::max(0.0, mean_vy2_ - mean_vy_ * mean_vy_); }
  // The state a checkpoint keeps.
  double mean_vy() const { return mean_vy_; }
  double mean_vy2() const { return mean_vy2_; }
  void restore(double mean_vy, double mean_vy2) {
    mean_vy_ = mean_vy;
    mean_vy2_ = mean_vy2;
  }

private:
  double m_ = 1.0, w_ = 1.0, mean_vy_ = 0.0, mean_vy2_ = 0.0;
};

}  // namespace grainflow::ed
