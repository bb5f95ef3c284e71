#pragma once
// The space the vehicle itself has occupied: its body's box (in the LiDAR frame) at every earlier
// pose. Nothing static can be there, since the vehicle drove through it; returns found there come
// from things that moved in behind it (a car following in the same lane leaves a trail of such
// returns, which would otherwise be meshed into a wall across the road) or from the vehicle itself.
// The mapper drops them before they reach the voxel map.
//
// Poses are kept on a horizontal grid of cells at least as wide as the box's reach, so a query
// looks at the poses of one cell and its 8 neighbours, and most points (far from the path) at none.

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "artemis/core/transform.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::mapping {

class SweptVolume {
 public:
  // `box_L`: the vehicle's body in the LiDAR frame; an empty box turns the volume off.
  explicit SweptVolume(const Eigen::AlignedBox3f& box_L);

  [[nodiscard]] bool enabled() const { return !box_.isEmpty(); }
  // Adds the box at pose T_W_L (after the frame taken there is mapped).
  void add(const Isometry3d& T_W_L);
  // Prepares queries of points within `radius` (horizontally) of `centre_W`: a dense window of
  // cells, each with the poses that can reach it, so that such a query costs one array lookup
  // when no pose is near. Call after add() and before contains().
  void focus(const Eigen::Vector3f& centre_W, float radius);
  // Whether world point p lies in the box at any added pose. Thread-safe between focus() calls.
  [[nodiscard]] bool contains(const Eigen::Vector3f& p_W) const;

  // Checkpoints (mapping/checkpoint.cpp): the poses so far (focus() is called again each frame).
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);
  [[nodiscard]] std::size_t poses() const { return poses_.size(); }

 private:
  struct Pose {
    Eigen::Matrix3f R_L_W;
    Eigen::Vector3f t_L_W;
  };
  using Cell = std::uint64_t;
  [[nodiscard]] std::int32_t cellIndex(float coordinate) const;  // along x or y
  static Cell key(std::int32_t ix, std::int32_t iy);

  Eigen::AlignedBox3f box_;
  float cell_m_ = 1.0f;
  std::vector<Pose> poses_;
  std::vector<std::pair<std::int32_t, std::int32_t>> origin_cells_;  // per pose: the cell of its origin
  std::unordered_map<Cell, std::vector<std::uint32_t>> cells_;       // cell -> poses whose origin is in it
  // The focus window: cells [ix0, ix0 + n) x [iy0, iy0 + n), each with the poses of its 3 x 3
  // neighbourhood (CSR).
  std::int32_t ix0_ = 0;
  std::int32_t iy0_ = 0;
  std::int32_t n_ = 0;
  std::vector<std::uint32_t> window_offsets_;
  std::vector<std::uint32_t> window_poses_;
};

}  // namespace artemis::mapping
