#include "artemis/mapping/swept_volume.hpp"

#include <algorithm>
#include <cmath>

namespace artemis::mapping {

SweptVolume::SweptVolume(const Eigen::AlignedBox3f& box_L) : box_(box_L) {
  if (box_.isEmpty()) return;
  // A point in the box is no farther from the pose's origin than the box's farthest corner.
  float reach = 0.0f;
  for (int c = 0; c < 8; ++c) {
    reach = std::max(reach, box_.corner(static_cast<Eigen::AlignedBox3f::CornerType>(c)).norm());
  }
  cell_m_ = std::max(reach, 0.5f);
}

std::int32_t SweptVolume::cellIndex(float coordinate) const {
  return static_cast<std::int32_t>(std::floor(coordinate / cell_m_));
}

SweptVolume::Cell SweptVolume::key(std::int32_t ix, std::int32_t iy) {
  return (static_cast<Cell>(static_cast<std::uint32_t>(ix)) << 32) | static_cast<std::uint32_t>(iy);
}

void SweptVolume::add(const Isometry3d& T_W_L) {
  if (!enabled()) return;
  const Isometry3d T_L_W = T_W_L.inverse();
  const Eigen::Vector3d t = T_W_L.translation();
  if (!t.allFinite() || !(t.cwiseAbs().maxCoeff() < 1e6)) return;  // a broken pose: as the voxel map refuses
  const std::int32_t ix = cellIndex(static_cast<float>(t.x()));
  const std::int32_t iy = cellIndex(static_cast<float>(t.y()));
  cells_[key(ix, iy)].push_back(static_cast<std::uint32_t>(poses_.size()));
  origin_cells_.emplace_back(ix, iy);
  poses_.push_back({T_L_W.linear().cast<float>(), T_L_W.translation().cast<float>()});
}

void SweptVolume::focus(const Eigen::Vector3f& centre_W, float radius) {
  n_ = 0;
  window_offsets_.clear();
  window_poses_.clear();
  if (poses_.empty() || !centre_W.allFinite() || !(radius > 0.0f) || !(radius < 1e5f)) return;
  ix0_ = cellIndex(centre_W.x() - radius);
  iy0_ = cellIndex(centre_W.y() - radius);
  n_ = static_cast<std::int32_t>(std::ceil(2.0f * radius / cell_m_)) + 2;
  const auto cells = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
  window_offsets_.assign(cells + 1, 0);
  // Each pose near the window goes to the window cells of its own cell's 3 x 3 neighbourhood:
  // counted, then placed (in pose order).
  const auto each_reach = [&](const auto& visit) {
    for (std::uint32_t k = 0; k < poses_.size(); ++k) {
      const std::int32_t i = origin_cells_[k].first - ix0_;
      const std::int32_t j = origin_cells_[k].second - iy0_;
      if (i < -1 || j < -1 || i > n_ || j > n_) continue;
      for (std::int32_t di = -1; di <= 1; ++di) {
        for (std::int32_t dj = -1; dj <= 1; ++dj) {
          if (i + di >= 0 && j + dj >= 0 && i + di < n_ && j + dj < n_) {
            visit(static_cast<std::size_t>((i + di) * n_ + (j + dj)), k);
          }
        }
      }
    }
  };
  each_reach([&](std::size_t cell, std::uint32_t) { ++window_offsets_[cell + 1]; });
  for (std::size_t c = 0; c < cells; ++c) window_offsets_[c + 1] += window_offsets_[c];
  window_poses_.resize(window_offsets_[cells]);
  std::vector<std::uint32_t> fill(window_offsets_.begin(), window_offsets_.end() - 1);
  each_reach([&](std::size_t cell, std::uint32_t k) { window_poses_[fill[cell]++] = k; });
}

bool SweptVolume::contains(const Eigen::Vector3f& p_W) const {
  // Points beyond 1000 km (which the voxel map refuses) stay clear of the cell arithmetic.
  if (poses_.empty() || !p_W.allFinite() || !(p_W.cwiseAbs().maxCoeff() < 1e6f)) return false;
  const std::int32_t ix = cellIndex(p_W.x());
  const std::int32_t iy = cellIndex(p_W.y());
  if (ix >= ix0_ && iy >= iy0_ && ix < ix0_ + n_ && iy < iy0_ + n_) {
    const auto cell = static_cast<std::size_t>((ix - ix0_) * n_ + (iy - iy0_));
    for (std::uint32_t k = window_offsets_[cell]; k < window_offsets_[cell + 1]; ++k) {
      const Pose& pose = poses_[window_poses_[k]];
      if (box_.contains(pose.R_L_W * p_W + pose.t_L_W)) return true;
    }
    return false;
  }
  for (std::int32_t dx = -1; dx <= 1; ++dx) {
    for (std::int32_t dy = -1; dy <= 1; ++dy) {
      const auto it = cells_.find(key(ix + dx, iy + dy));
      if (it == cells_.end()) continue;
      for (const std::uint32_t k : it->second) {
        const Pose& pose = poses_[k];
        if (box_.contains(pose.R_L_W * p_W + pose.t_L_W)) return true;
      }
    }
  }
  return false;
}

}  // namespace artemis::mapping
