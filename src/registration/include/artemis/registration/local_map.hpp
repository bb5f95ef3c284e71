#pragma once
// The map a scan is registered against: world-frame points with their surface normals, hashed in
// voxels around the sensor. Each voxel keeps at most one point per sub-cell (subdivisions^3 of
// them), so scans of the same surface do not pile up; voxels farther than max_distance_m from the
// sensor are dropped, so memory and search cost follow the neighbourhood, not the drive.
//
// A point's normal is the direction of least spread of the map points within normal_radius_m
// (principal component analysis). It is computed when the point is added and recomputed while it
// is not yet valid (too few neighbours, or a neighbourhood that is not flat: a pole, a corner, a
// bush) and its voxel has grown by half since the last try; points without a valid normal are not
// used as correspondences.

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::registration {

struct LocalMapParams {
  // Voxels of 1 m with 0.25 m sub-cells: a nearest-neighbour query for correspondence distances up
  // to one voxel visits at most the 27 voxels around it, and the box test usually leaves one or two.
  double voxel_size_m = 1.0;
  int subdivisions = 4;           // 1..8
  double normal_radius_m = 0.5;   // neighbourhood of a normal estimate
  int min_normal_points = 6;      // fewer neighbours: no normal (yet)
  double max_flatness = 0.3;      // smallest / middle eigenvalue of a plane's covariance must stay below
  double max_distance_m = 100.0;  // voxels farther from the sensor are dropped
};

struct Correspondence {
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  float distance_sq = std::numeric_limits<float>::max();
};

class LocalMap {
 public:
  explicit LocalMap(const LocalMapParams& params);

  // Adds world-frame points (non-finite ones and those beyond 1000 km are refused and counted),
  // updates normals around them, then drops voxels farther than max_distance_m from `sensor_W`.
  // Returns how many points were added.
  std::size_t insert(const std::vector<Eigen::Vector3f>& points_W, const Eigen::Vector3f& sensor_W);

  // The nearest map point with a valid normal within `max_distance` of `query`.
  [[nodiscard]] std::optional<Correspondence> nearest(const Eigen::Vector3f& query, float max_distance) const;

  [[nodiscard]] bool empty() const { return point_count_ == 0; }
  [[nodiscard]] std::size_t pointCount() const { return point_count_; }
  [[nodiscard]] std::size_t voxelCount() const { return voxels_.size(); }
  [[nodiscard]] std::size_t rejectedPoints() const { return rejected_; }
  [[nodiscard]] const LocalMapParams& params() const { return params_; }
  // Every point and its normal (zero where not valid), in no particular order: for tests and dumps.
  void points(std::vector<Eigen::Vector3f>& points, std::vector<Eigen::Vector3f>& normals) const;

  // Checkpoints (registration/checkpoint.cpp): the whole map; load() into one with the same params.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  struct Key {
    std::int32_t x = 0, y = 0, z = 0;
    friend bool operator==(const Key&, const Key&) = default;
  };
  struct Surfel {
    Eigen::Vector3f point;
    Eigen::Vector3f normal;
  };
  struct Voxel {
    std::vector<Eigen::Vector3f> points;   // every kept point
    std::vector<std::uint8_t> has_normal;  // per point
    std::vector<Surfel> surfels;           // the points with a valid normal: what nearest() searches
    std::array<std::uint64_t, 8> occupied{};
    std::uint32_t touched = 0;          // the insert() that last added a point here
    std::uint32_t points_at_retry = 0;  // points.size() when normals were last retried
    std::uint32_t points_before = 0;    // points.size() before the current insert()
  };

  [[nodiscard]] Key keyOf(const Eigen::Vector3f& p) const;
  static std::uint64_t hashOf(const Key& key);
  [[nodiscard]] const Voxel* find(const Key& key) const;
  std::uint32_t findOrAdd(const Key& key);
  void rebuildTable();
  void prune(const Eigen::Vector3f& sensor_W);
  [[nodiscard]] Eigen::Vector3f estimateNormal(const Eigen::Vector3f& p) const;

  LocalMapParams params_;
  float voxel_;
  float inv_voxel_;
  float inv_sub_;
  std::vector<Voxel> voxels_;
  std::vector<Key> keys_;
  std::vector<std::uint32_t> table_;  // voxel index + 1; 0 = empty slot (linear probing)
  std::size_t point_count_ = 0;
  std::size_t rejected_ = 0;
  std::uint32_t inserts_ = 0;
  Eigen::Vector3f last_prune_sensor_ = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
};

}  // namespace artemis::registration
