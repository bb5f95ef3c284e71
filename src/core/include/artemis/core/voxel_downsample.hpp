#pragma once
// Voxel-grid downsampling: one point per occupied voxel (the centroid of the points inside).
// Voxel keys are 21-bit signed integers per axis, so |coordinate| / voxel_size_m must stay below
// 2^20 (about 52 km for 0.05 m voxels); points beyond are dropped and counted.

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "artemis/core/point_cloud.hpp"

namespace artemis {

// Accumulates clouds (e.g. scan after scan) into voxels; memory grows with occupied voxels only.
class VoxelAccumulator {
 public:
  explicit VoxelAccumulator(double voxel_size_m);

  // Adds `cloud` transformed by T_out_cloud.
  void add(const PointCloud& cloud, const Isometry3d& T_out_cloud = Isometry3d::Identity());

  // Centroids in order of first occurrence (deterministic); intensity averaged when every added
  // cloud had it; the label of the first point of the voxel when every added cloud had labels.
  [[nodiscard]] PointCloud centroids() const;
  [[nodiscard]] std::size_t voxelCount() const { return acc_.size(); }
  [[nodiscard]] std::size_t outOfBounds() const { return out_of_bounds_; }

 private:
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double intensity_sum = 0.0;
    std::uint32_t label = 0;
    std::uint32_t count = 0;
  };
  double inv_voxel_size_;
  std::unordered_map<std::uint64_t, std::uint32_t> slot_of_;
  std::vector<Cell> acc_;
  std::size_t out_of_bounds_ = 0;
  bool all_intensity_ = true;
  bool all_labels_ = true;
};

struct DownsampleResult {
  PointCloud cloud;
  std::size_t out_of_bounds = 0;  // points dropped for lying outside the key range
};

DownsampleResult voxelDownsample(const PointCloud& cloud, double voxel_size_m);

}  // namespace artemis
