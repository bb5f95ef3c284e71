#include "artemis/mapping/frame_ground.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace artemis::mapping {

FrameGround::FrameGround(const PointCloud& points_L, const Isometry3d& T_W_L, const FrameGroundParams& params)
    : FrameGround(std::span<const Eigen::Vector3f>(points_L.points), T_W_L, params) {}

FrameGround::FrameGround(std::span<const Eigen::Vector3f> points_L, const Isometry3d& T_W_L,
                         const FrameGroundParams& params)
    : params_(params) {
  if (!(params.cell_m > 0.0) || !(params.radius_m > params.cell_m) || params.search_cells < 0 ||
      params.radius_m / params.cell_m > 4096.0) {
    throw std::invalid_argument(
        "frame ground: cell_m > 0, radius_m > cell_m (at most 4096 cells) and search_cells >= 0");
  }
  side_ = 2 * static_cast<int>(std::ceil(params.radius_m / params.cell_m));
  lowest_.assign(static_cast<std::size_t>(side_) * static_cast<std::size_t>(side_),
                 std::numeric_limits<float>::infinity());
  const Isometry3d T_L_W = T_W_L.inverse();
  R_L_W_ = T_L_W.linear().cast<float>();
  t_L_W_ = T_L_W.translation().cast<float>();
  // World z of a LiDAR point: the third row of T_W_L.
  const Eigen::Vector3f up = T_W_L.linear().row(2).transpose().cast<float>();
  const auto up_t = static_cast<float>(T_W_L.translation().z());
  const auto inv_cell = static_cast<float>(1.0 / params.cell_m);
  const int half = side_ / 2;
  for (const Eigen::Vector3f& p : points_L) {
    const int x = static_cast<int>(std::floor(p.x() * inv_cell)) + half;
    const int y = static_cast<int>(std::floor(p.y() * inv_cell)) + half;
    if (x < 0 || y < 0 || x >= side_ || y >= side_) continue;
    float& low = lowest_[static_cast<std::size_t>(y) * static_cast<std::size_t>(side_) + static_cast<std::size_t>(x)];
    low = std::min(low, up.dot(p) + up_t);
  }
}

float FrameGround::heightAbove(const Eigen::Vector3f& p_W) const {
  constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();
  if (lowest_.empty() || !p_W.allFinite()) return kUnknown;
  const Eigen::Vector3f p_L = R_L_W_ * p_W + t_L_W_;
  const auto inv_cell = static_cast<float>(1.0 / params_.cell_m);
  const int half = side_ / 2;
  const int x = static_cast<int>(std::floor(p_L.x() * inv_cell)) + half;
  const int y = static_cast<int>(std::floor(p_L.y() * inv_cell)) + half;
  const int r = params_.search_cells;
  float low = std::numeric_limits<float>::infinity();
  for (int yy = std::max(0, y - r); yy <= std::min(side_ - 1, y + r); ++yy) {
    for (int xx = std::max(0, x - r); xx <= std::min(side_ - 1, x + r); ++xx) {
      low = std::min(
          low, lowest_[static_cast<std::size_t>(yy) * static_cast<std::size_t>(side_) + static_cast<std::size_t>(xx)]);
    }
  }
  return std::isfinite(low) ? p_W.z() - low : kUnknown;
}

}  // namespace artemis::mapping
