#include "artemis/registration/local_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "artemis/core/cell_hash.hpp"

namespace artemis::registration {

LocalMap::LocalMap(const LocalMapParams& params) : params_(params) {
  if (!(params.voxel_size_m > 0.0) || params.subdivisions < 1 || params.subdivisions > 8 ||
      !(params.normal_radius_m > 0.0) || params.min_normal_points < 3 || !(params.max_distance_m > 0.0)) {
    throw std::invalid_argument(
        "LocalMap: voxel_size_m, normal_radius_m, max_distance_m must be > 0, "
        "subdivisions in 1..8 and min_normal_points >= 3 (voxel " +
        std::to_string(params.voxel_size_m) + ", subdivisions " + std::to_string(params.subdivisions) + ")");
  }
  voxel_ = static_cast<float>(params.voxel_size_m);
  inv_voxel_ = 1.0f / voxel_;
  inv_sub_ = static_cast<float>(params.subdivisions) * inv_voxel_;
  table_.assign(std::size_t{1} << 12, 0);
}

LocalMap::Key LocalMap::keyOf(const Eigen::Vector3f& p) const {
  return {static_cast<std::int32_t>(std::floor(p.x() * inv_voxel_)),
          static_cast<std::int32_t>(std::floor(p.y() * inv_voxel_)),
          static_cast<std::int32_t>(std::floor(p.z() * inv_voxel_))};
}

std::uint64_t LocalMap::hashOf(const Key& key) {
  return hashCell(key.x, key.y, key.z);
}

const LocalMap::Voxel* LocalMap::find(const Key& key) const {
  const std::size_t mask = table_.size() - 1;
  std::size_t slot = static_cast<std::size_t>(hashOf(key)) & mask;
  while (table_[slot] != 0) {
    const std::uint32_t index = table_[slot] - 1;
    if (keys_[index] == key) return &voxels_[index];
    slot = (slot + 1) & mask;
  }
  return nullptr;
}

std::uint32_t LocalMap::findOrAdd(const Key& key) {
  const std::size_t mask = table_.size() - 1;
  std::size_t slot = static_cast<std::size_t>(hashOf(key)) & mask;
  while (table_[slot] != 0) {
    const std::uint32_t index = table_[slot] - 1;
    if (keys_[index] == key) return index;
    slot = (slot + 1) & mask;
  }
  const auto index = static_cast<std::uint32_t>(voxels_.size());
  voxels_.emplace_back();
  keys_.push_back(key);
  table_[slot] = index + 1;
  if (2 * voxels_.size() > table_.size()) {  // load factor at most 1/2
    table_.assign(table_.size() * 2, 0);
    rebuildTable();
  }
  return index;
}

void LocalMap::rebuildTable() {
  std::fill(table_.begin(), table_.end(), 0u);
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    std::size_t slot = static_cast<std::size_t>(hashOf(keys_[i])) & mask;
    while (table_[slot] != 0) slot = (slot + 1) & mask;
    table_[slot] = static_cast<std::uint32_t>(i + 1);
  }
}

std::size_t LocalMap::insert(const std::vector<Eigen::Vector3f>& points_W, const Eigen::Vector3f& sensor_W) {
  ++inserts_;
  const int n = params_.subdivisions;
  std::vector<std::uint32_t> touched;
  std::size_t added = 0;
  Key last_key{std::numeric_limits<std::int32_t>::min(), 0, 0};
  std::uint32_t index = 0;
  for (const Eigen::Vector3f& p : points_W) {
    if (!p.allFinite() || !(p.cwiseAbs().maxCoeff() < 1e6f)) {
      ++rejected_;
      continue;
    }
    const Key key = keyOf(p);
    const auto sub = [&](float c, std::int32_t k) {
      return std::clamp(static_cast<int>((c - static_cast<float>(k) * voxel_) * inv_sub_), 0, n - 1);
    };
    const int cell = (sub(p.x(), key.x) * n + sub(p.y(), key.y)) * n + sub(p.z(), key.z);
    if (!(key == last_key)) {  // successive points of a scan often share a voxel
      index = findOrAdd(key);
      last_key = key;
    }
    Voxel& v = voxels_[index];
    std::uint64_t& word = v.occupied[static_cast<std::size_t>(cell >> 6)];
    const std::uint64_t bit = std::uint64_t{1} << (cell & 63);
    if ((word & bit) != 0) continue;
    word |= bit;
    if (v.touched != inserts_) v.points_before = static_cast<std::uint32_t>(v.points.size());
    v.points.push_back(p);
    v.has_normal.push_back(0);
    if (v.touched != inserts_) {
      v.touched = inserts_;
      touched.push_back(index);
    }
    ++added;
  }
  point_count_ += added;

  // Normals of the new points, and of older points without one whose voxel grew by half since the
  // last try (a bush stays a bush: trying it every frame cost more than all the rest).
  struct Job {
    std::uint32_t voxel;
    std::uint32_t point;
  };
  std::vector<Job> jobs;
  for (const std::uint32_t voxel : touched) {
    Voxel& v = voxels_[voxel];
    const auto size = static_cast<std::uint32_t>(v.points.size());
    const bool retry = 2 * size >= 3 * v.points_at_retry;
    for (std::uint32_t i = retry ? 0 : v.points_before; i < size; ++i) {
      if (v.has_normal[i] == 0) jobs.push_back({voxel, i});
    }
    if (retry) v.points_at_retry = size;
  }
  // Reads positions only: in parallel, then the surfels appended in job order (deterministic).
  std::vector<Eigen::Vector3f> normals(jobs.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, jobs.size(), 256), [&](const auto& range) {
    for (std::size_t j = range.begin(); j < range.end(); ++j) {
      normals[j] = estimateNormal(voxels_[jobs[j].voxel].points[jobs[j].point]);
    }
  });
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    if (normals[j].isZero()) continue;
    Voxel& v = voxels_[jobs[j].voxel];
    v.has_normal[jobs[j].point] = 1;
    v.surfels.push_back({v.points[jobs[j].point], normals[j]});
  }
  prune(sensor_W);
  return added;
}

void LocalMap::prune(const Eigen::Vector3f& sensor_W) {
  // Checking every voxel costs the whole map: do it each time the sensor has moved a tenth of the
  // keep distance.
  const auto keep = static_cast<float>(params_.max_distance_m);
  if ((sensor_W - last_prune_sensor_).norm() < 0.1f * keep) return;
  last_prune_sensor_ = sensor_W;
  std::size_t out = 0;
  for (std::size_t i = 0; i < voxels_.size(); ++i) {
    const Key& k = keys_[i];
    const Eigen::Vector3f centre =
        (Eigen::Vector3f(static_cast<float>(k.x), static_cast<float>(k.y), static_cast<float>(k.z)) +
         Eigen::Vector3f::Constant(0.5f)) *
        voxel_;
    if ((centre - sensor_W).norm() > keep) {
      point_count_ -= voxels_[i].points.size();
      continue;
    }
    if (out != i) {
      voxels_[out] = std::move(voxels_[i]);
      keys_[out] = keys_[i];
    }
    ++out;
  }
  if (out == voxels_.size()) return;
  voxels_.resize(out);
  keys_.resize(out);
  rebuildTable();
}

Eigen::Vector3f LocalMap::estimateNormal(const Eigen::Vector3f& p) const {
  const auto r = static_cast<float>(params_.normal_radius_m);
  const float r2 = r * r;
  const Key lo = keyOf(p - Eigen::Vector3f::Constant(r));
  const Key hi = keyOf(p + Eigen::Vector3f::Constant(r));
  // Moments of the neighbours relative to p: small numbers, so float loses nothing that matters.
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  float xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  int count = 0;
  for (std::int32_t x = lo.x; x <= hi.x; ++x) {
    for (std::int32_t y = lo.y; y <= hi.y; ++y) {
      for (std::int32_t z = lo.z; z <= hi.z; ++z) {
        const Voxel* v = find({x, y, z});
        if (v == nullptr) continue;
        for (const Eigen::Vector3f& q : v->points) {
          const Eigen::Vector3f d = q - p;
          if (d.squaredNorm() > r2) continue;
          sum += d;
          xx += d.x() * d.x();
          xy += d.x() * d.y();
          xz += d.x() * d.z();
          yy += d.y() * d.y();
          yz += d.y() * d.z();
          zz += d.z() * d.z();
          ++count;
        }
      }
    }
  }
  if (count < params_.min_normal_points) return Eigen::Vector3f::Zero();
  const Eigen::Vector3d mean = sum.cast<double>() / count;
  Eigen::Matrix3d outer;
  outer << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  const Eigen::Matrix3d cov = outer / count - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov);
  const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
  if (!(lambda(0) <= params_.max_flatness * lambda(1)) || !(lambda(1) > 0.0)) return Eigen::Vector3f::Zero();
  return eig.eigenvectors().col(0).normalized().cast<float>();
}

std::optional<Correspondence> LocalMap::nearest(const Eigen::Vector3f& query, float max_distance) const {
  if (!query.allFinite() || !(max_distance > 0.0f)) return std::nullopt;
  Correspondence best;
  best.distance_sq = max_distance * max_distance;
  const Surfel* found = nullptr;
  const auto search = [&](const Voxel& v) {
    for (const Surfel& s : v.surfels) {
      const float d2 = (s.point - query).squaredNorm();
      if (d2 < best.distance_sq) {
        best.distance_sq = d2;
        found = &s;
      }
    }
  };
  const Key k = keyOf(query);
  if (const Voxel* v = find(k)) search(*v);
  const int reach = std::max(1, static_cast<int>(std::ceil(max_distance * inv_voxel_)));
  // Squared distance from the query to the slab of voxels at offset d along one axis.
  const auto slab = [&](float c, std::int32_t kk, int d) {
    if (d == 0) return 0.0f;
    const float lo = static_cast<float>(kk + d) * voxel_;
    const float gap = d < 0 ? c - (lo + voxel_) : lo - c;
    return gap * gap;
  };
  for (int dx = -reach; dx <= reach; ++dx) {
    const float gx = slab(query.x(), k.x, dx);
    if (gx >= best.distance_sq) continue;
    for (int dy = -reach; dy <= reach; ++dy) {
      const float gxy = gx + slab(query.y(), k.y, dy);
      if (gxy >= best.distance_sq) continue;
      for (int dz = -reach; dz <= reach; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        // Skip voxels that cannot hold anything nearer than the best so far.
        if (gxy + slab(query.z(), k.z, dz) >= best.distance_sq) continue;
        if (const Voxel* v = find({k.x + dx, k.y + dy, k.z + dz})) search(*v);
      }
    }
  }
  if (found == nullptr) return std::nullopt;
  best.point = found->point;
  best.normal = found->normal;
  return best;
}

void LocalMap::points(std::vector<Eigen::Vector3f>& points, std::vector<Eigen::Vector3f>& normals) const {
  points.clear();
  normals.clear();
  for (const Voxel& v : voxels_) {
    for (const Surfel& s : v.surfels) {
      points.push_back(s.point);
      normals.push_back(s.normal);
    }
    for (std::size_t i = 0; i < v.points.size(); ++i) {
      if (v.has_normal[i] == 0) {
        points.push_back(v.points[i]);
        normals.emplace_back(Eigen::Vector3f::Zero());
      }
    }
  }
}

}  // namespace artemis::registration
