#include "render/layers/camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace grainflow::render {

namespace {
Mat4 ortho(double l, double r, double b, double t, double n, double f) {
  Mat4 m = Mat4::Identity();
  m(0, 0) = float(2.0 / (r - l));
  m(1, 1) = float(2.0 / (t - b));
  m(2, 2) = float(-2.0 / (f - n));
  m(0, 3) = float(-(r + l) / (r - l));
  m(1, 3) = float(-(t + b) / (t - b));
  m(2, 3) = float(-(f + n) / (f - n));
  return m;
}
Mat4 perspective(double fov_y_rad, double aspect, double n, double f) {
  const double t = 1.0 / std::tan(fov_y_rad / 2);
  Mat4 m = Mat4::Zero();
  m(0, 0) = float(t / aspect);
  m(1, 1) = float(t);
  m(2, 2) = float((f + n) / (n - f));
  m(2, 3) = float(2 * f * n / (n - f));
  m(3, 2) = -1.0f;
  return m;
}
Mat4 look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d f = (target - eye).normalized();
  const Eigen::Vector3d s = f.cross(up).normalized();
  const Eigen::Vector3d u = s.cross(f);
  Mat4 m = Mat4::Identity();
  m.block<1, 3>(0, 0) = s.cast<float>().transpose();
  m.block<1, 3>(1, 0) = u.cast<float>().transpose();
  m.block<1, 3>(2, 0) = -f.cast<float>().transpose();
  m(0, 3) = float(-s.dot(eye));
  m(1, 3) = float(-u.dot(eye));
  m(2, 3) = float(f.dot(eye));
  return m;
}
}  // namespace

ViewTransform fit_2d(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int width, int height, double margin) {
  const double w = std::max(hi.x() - lo.x(), 1e-12), h = std::max(hi.y() - lo.y(), 1e-12);
  const double usable_w = width * (1 - 2 * margin), usable_h = height * (1 - 2 * margin);
  const double scale = std::min(usable_w / w, usable_h / h);  // pixels per unit
  const double cx = 0.5 * (lo.x() + hi.x()), cy = 0.5 * (lo.y() + hi.y());
  const double half_w = 0.5 * width / scale, half_h = 0.5 * height / scale;
  ViewTransform v;
  v.proj = ortho(cx - half_w, cx + half_w, cy - half_h, cy + half_h, -1, 1);
  v.pixels_per_unit = float(scale);
  return v;
}

ViewTransform fit_2d(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const OrbitCamera& cam, int width,
                     int height) {
  if (cam.zoom == 1.0 && !cam.target) return fit_2d(lo, hi, width, height);
  const Eigen::Vector2d centre = cam.target ? Eigen::Vector2d(cam.target->head<2>()) : Eigen::Vector2d(0.5 * (lo + hi));
  const Eigen::Vector2d half = 0.5 * (hi - lo) / std::max(cam.zoom, 1e-6);
  return fit_2d(centre - half, centre + half, width, height);
}

ViewTransform fit_3d(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const OrbitCamera& cam, int width,
                     int height) {
  const Eigen::Vector3d centre = cam.target ? *cam.target : Eigen::Vector3d(0.5 * (lo + hi));
  const double radius = std::max(0.5 * (hi - lo).norm(), 1e-12) / std::max(cam.zoom, 1e-6);
  // What the near and far planes must hold: the whole box, seen from the target.
  double reach = std::max(0.5 * (hi - lo).norm(), 1e-12);
  for (int corner = 0; cam.target && corner < 8; ++corner) {
    const Eigen::Vector3d p((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(), (corner & 4) ? hi.z() : lo.z());
    reach = std::max(reach, (p - centre).norm());
  }
  const double az = cam.azimuth_deg * M_PI / 180, el = cam.elevation_deg * M_PI / 180;
  const Eigen::Vector3d dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const double aspect = double(width) / height;
  const double fov = cam.fov_y_deg * M_PI / 180;
  // Distance at which the bounding sphere fits both the vertical and horizontal FOV.
  const double fov_min = std::min(fov, 2 * std::atan(std::tan(fov / 2) * aspect));
  const double dist = cam.distance ? *cam.distance : radius / std::sin(fov_min / 2) * 1.02;
  ViewTransform v;
  v.view = look_at(centre + dist * dir, centre, Eigen::Vector3d::UnitZ());
  if (cam.orthographic) {
    const double half_h = radius * 1.05 * std::max(1.0, 1.0 / aspect);
    v.proj = ortho(-half_h * aspect, half_h * aspect, -half_h, half_h, dist - 2 * reach, dist + 2 * reach);
    v.pixels_per_unit = float(height / (2 * half_h));
  } else {
    v.proj = perspective(fov, aspect, std::max(dist - 2 * reach, dist * 1e-3), dist + 2 * reach);
    v.pixels_per_unit = float(height / (2 * dist * std::tan(fov / 2)));
  }
  return v;
}

}  // namespace grainflow::render
