// The registration's state in a checkpoint (see artemis/core/archive.hpp): what an odometry made
// with the same params needs, after load(), to register the next scans exactly as the saved one.

#include <string>

#include "artemis/core/archive.hpp"
#include "artemis/registration/local_map.hpp"
#include "artemis/registration/odometry.hpp"

namespace artemis::registration {

void LocalMap::save(ArchiveWriter& out) const {
  out.section("local-map");
  out.value(params_.voxel_size_m);
  out.value(params_.subdivisions);
  out.value(static_cast<std::uint64_t>(voxels_.size()));
  for (const Voxel& v : voxels_) {
    out.array(v.points);
    out.array(v.has_normal);
    std::vector<Eigen::Vector3f> points;
    std::vector<Eigen::Vector3f> normals;
    for (const Surfel& s : v.surfels) {
      points.push_back(s.point);
      normals.push_back(s.normal);
    }
    out.array(points);
    out.array(normals);
    out.value(v.occupied);
    out.value(v.touched);
    out.value(v.points_at_retry);
    out.value(v.points_before);
  }
  out.array(keys_);
  out.array(table_);
  out.value(static_cast<std::uint64_t>(point_count_));
  out.value(static_cast<std::uint64_t>(rejected_));
  out.value(inserts_);
  out.value(last_prune_sensor_);
}

void LocalMap::load(ArchiveReader& in) {
  in.section("local-map");
  if (in.value<double>() != params_.voxel_size_m || in.value<int>() != params_.subdivisions) {
    in.fail("the checkpoint's registration map has other voxels than this run's");
  }
  voxels_.resize(static_cast<std::size_t>(in.value<std::uint64_t>()));
  for (Voxel& v : voxels_) {
    in.array(v.points);
    in.array(v.has_normal);
    std::vector<Eigen::Vector3f> points;
    std::vector<Eigen::Vector3f> normals;
    in.array(points);
    in.array(normals);
    if (normals.size() != points.size() || v.has_normal.size() != v.points.size()) {
      in.fail("a registration voxel's normals do not match its points");
    }
    v.surfels.resize(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) v.surfels[k] = {points[k], normals[k]};
    in.value(v.occupied);
    in.value(v.touched);
    in.value(v.points_at_retry);
    in.value(v.points_before);
  }
  in.array(keys_);
  in.array(table_);
  if (keys_.size() != voxels_.size() || table_.empty() || (table_.size() & (table_.size() - 1)) != 0) {
    in.fail("the registration map's keys or hash table do not match its voxels");
  }
  for (const std::uint32_t slot : table_) {
    if (slot > voxels_.size()) in.fail("the registration map's hash table names a voxel it does not have");
  }
  point_count_ = static_cast<std::size_t>(in.value<std::uint64_t>());
  rejected_ = static_cast<std::size_t>(in.value<std::uint64_t>());
  in.value(inserts_);
  in.value(last_prune_sensor_);
}

void Odometry::save(ArchiveWriter& out) const {
  out.section("odometry");
  map_.save(out);
  out.value(static_cast<std::uint8_t>(last_.has_value()));
  out.isometry(last_.value_or(Isometry3d::Identity()));
  out.value(velocity_);
  out.value(error_sq_sum_);
  out.value(error_samples_);
}

void Odometry::load(ArchiveReader& in) {
  in.section("odometry");
  map_.load(in);
  const bool has_last = in.value<std::uint8_t>() != 0;
  const Isometry3d last = in.isometry();
  last_ = has_last ? std::optional<Isometry3d>(last) : std::nullopt;
  in.value(velocity_);
  in.value(error_sq_sum_);
  in.value(error_samples_);
}

}  // namespace artemis::registration
