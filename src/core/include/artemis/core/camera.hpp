#pragma once
// Pinhole camera of a rectified image. Projection of a point p_C in the camera frame
// (x right, y down, z forward): u = fx * x / z + cx, v = fy * y / z + cy.

#include <Eigen/Core>
#include <optional>

namespace artemis {

struct PinholeCamera {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;

  // Smallest depth accepted in front of the camera; points closer or behind are rejected.
  static constexpr double kMinDepthM = 1e-3;

  [[nodiscard]] Eigen::Matrix3d K() const;

  // Pixel coordinates of p_C, or nothing when the point is behind (or on) the camera plane.
  // The pixel may lie outside the image: check with inImage().
  [[nodiscard]] std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_C) const;

  // Pixel centres are at integer coordinates; the image covers [-0.5, width - 0.5).
  [[nodiscard]] bool inImage(const Eigen::Vector2d& uv_px) const;

  [[nodiscard]] bool valid() const { return width_px > 0 && height_px > 0 && fx_px > 0.0 && fy_px > 0.0; }
};

// The same projection in single precision, for loops over many points (no checks: the caller
// rejects points with z <= kMinDepthM first).
struct PinholeProjector {
  explicit PinholeProjector(const PinholeCamera& c)
      : fx(static_cast<float>(c.fx_px)),
        fy(static_cast<float>(c.fy_px)),
        cx(static_cast<float>(c.cx_px)),
        cy(static_cast<float>(c.cy_px)) {}
  [[nodiscard]] Eigen::Vector2f operator()(const Eigen::Vector3f& p_C) const {
    return {fx * p_C.x() / p_C.z() + cx, fy * p_C.y() / p_C.z() + cy};
  }
  float fx, fy, cx, cy;
};

}  // namespace artemis
