#include "artemis/core/voxel_downsample.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace artemis {

namespace {

constexpr std::int64_t kKeyLimit = std::int64_t{1} << 20;

std::uint64_t packKey(const Eigen::Vector3d& k) {
  const auto u = [](double v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(v) + kKeyLimit) & 0x1FFFFFu;
  };
  return u(k.x()) | (u(k.y()) << 21) | (u(k.z()) << 42);
}

}  // namespace

VoxelAccumulator::VoxelAccumulator(double voxel_size_m) {
  if (!(voxel_size_m > 0.0) || !std::isfinite(voxel_size_m)) {
    throw std::invalid_argument("VoxelAccumulator: voxel_size_m must be > 0, got " + std::to_string(voxel_size_m));
  }
  inv_voxel_size_ = 1.0 / voxel_size_m;
}

void VoxelAccumulator::add(const PointCloud& cloud, const Isometry3d& T_out_cloud) {
  const bool has_intensity = !cloud.intensity.empty();
  const bool has_labels = !cloud.labels.empty();
  all_intensity_ = all_intensity_ && has_intensity;
  all_labels_ = all_labels_ && has_labels;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = T_out_cloud * cloud.points[i].cast<double>();
    const Eigen::Vector3d k = (p * inv_voxel_size_).array().floor();
    if (!p.allFinite() || (k.array().abs() >= static_cast<double>(kKeyLimit)).any()) {
      ++out_of_bounds_;
      continue;
    }
    const auto [it, inserted] = slot_of_.try_emplace(packKey(k), static_cast<std::uint32_t>(acc_.size()));
    if (inserted) {
      acc_.emplace_back();
      if (has_labels) acc_.back().label = cloud.labels[i];
    }
    Cell& c = acc_[it->second];
    c.sum += p;
    if (has_intensity) c.intensity_sum += cloud.intensity[i];
    ++c.count;
  }
}

PointCloud VoxelAccumulator::centroids() const {
  PointCloud out;
  out.points.reserve(acc_.size());
  for (const auto& c : acc_) out.points.push_back((c.sum / c.count).cast<float>());
  if (all_intensity_ && !acc_.empty()) {
    out.intensity.reserve(acc_.size());
    for (const auto& c : acc_) out.intensity.push_back(static_cast<float>(c.intensity_sum / c.count));
  }
  if (all_labels_ && !acc_.empty()) {
    out.labels.reserve(acc_.size());
    for (const auto& c : acc_) out.labels.push_back(c.label);
  }
  return out;
}

DownsampleResult voxelDownsample(const PointCloud& cloud, double voxel_size_m) {
  VoxelAccumulator acc(voxel_size_m);
  acc.add(cloud);
  return {acc.centroids(), acc.outOfBounds()};
}

}  // namespace artemis
