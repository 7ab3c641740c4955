// Cameras: a 2D orthographic view that fits a rectangle into the viewport keeping the
// aspect ratio, and a 3D orbit camera (perspective or orthographic) around a box.
#pragma once
#include <optional>

#include <Eigen/Core>

namespace grainflow::render {

using Mat4 = Eigen::Matrix4f;

struct ViewTransform {
  Mat4 view = Mat4::Identity();
  Mat4 proj = Mat4::Identity();
  Mat4 view_proj() const { return proj * view; }
  float pixels_per_unit = 1.0f;  // for 2D and orthographic views: world length → pixels
  // Normalised device coordinates ([−1, 1]², y up) of the world point (x, y, 0).
  Eigen::Vector2d ndc(double x, double y) const {
    const Eigen::Vector4f c = view_proj() * Eigen::Vector4f(float(x), float(y), 0.f, 1.f);
    return {c.x() / c.w(), c.y() / c.w()};
  }
};

// Maps [lo, hi] (world x, y) into a viewport of width × height pixels, centred, with
// `margin` (fraction of the viewport) on the tighter side.
ViewTransform fit_2d(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int width, int height,
                     double margin = 0.03);

struct OrbitCamera {
  double azimuth_deg = 35.0;    // around the vertical (z) axis, from +x towards +y
  double elevation_deg = 25.0;  // above the horizontal plane
  double fov_y_deg = 30.0;
  bool orthographic = false;
  double zoom = 1.0;            // > 1 moves closer (2D too: shows 1/zoom of the box)
  // The point looked at (2D: the centre of the view); unset: the box's centre.
  std::optional<Eigen::Vector3d> target;
  // Eye to target, world units (3D); unset: where the box, over zoom, just fits.
  std::optional<double> distance;
};

// The 2D view of [lo, hi] (x, y) through the camera's zoom and target: fit_2d of the box,
// or of a window of 1/zoom its size around the target.
ViewTransform fit_2d(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const OrbitCamera& cam, int width,
                     int height);

// Frames the box [lo, hi] (z up) as seen by the orbit camera.
ViewTransform fit_3d(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const OrbitCamera& cam, int width,
                     int height);

}  // namespace grainflow::render
