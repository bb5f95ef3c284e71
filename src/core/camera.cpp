#include "artemis/core/camera.hpp"

namespace artemis {

Eigen::Matrix3d PinholeCamera::K() const {
  Eigen::Matrix3d k;
  k << fx_px, 0.0, cx_px, 0.0, fy_px, cy_px, 0.0, 0.0, 1.0;
  return k;
}

std::optional<Eigen::Vector2d> PinholeCamera::project(const Eigen::Vector3d& p_C) const {
  if (!(p_C.z() > kMinDepthM)) return std::nullopt;  // also rejects NaN depth
  const double inv_z = 1.0 / p_C.z();
  return Eigen::Vector2d(fx_px * p_C.x() * inv_z + cx_px, fy_px * p_C.y() * inv_z + cy_px);
}

bool PinholeCamera::inImage(const Eigen::Vector2d& uv_px) const {
  return uv_px.x() >= -0.5 && uv_px.y() >= -0.5 && uv_px.x() < width_px - 0.5 && uv_px.y() < height_px - 0.5;
}

}  // namespace artemis
