#pragma once
// The ground around the sensor in one frame: the lowest return (world z) of each cell of a 2-D grid
// laid in the LiDAR frame's x-y plane, centred on the sensor. heightAbove(p) is p's world z minus
// the lowest return within search_cells of p's cell: the road wherever some road is visible
// nearby, which it is around a car (1.8 m wide, so a 5 x 5 m neighbourhood reaches past it).
//
// Assumes the world's z axis points up (the recording's first LiDAR frame on a level vehicle, as
// on KITTI and the simulator). Building it is one pass over the frame's points into a dense
// array; nothing is kept between frames.

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/point_cloud.hpp"
#include "artemis/core/transform.hpp"

namespace artemis::mapping {

struct FrameGroundParams {
  double cell_m = 1.0;
  double radius_m = 40.0;  // half the grid's side: points farther out are not used
  int search_cells = 2;    // the neighbourhood of heightAbove(): (2 * search_cells + 1)^2 cells
};

class FrameGround {
 public:
  FrameGround() = default;
  FrameGround(const PointCloud& points_L, const Isometry3d& T_W_L, const FrameGroundParams& params = {});
  FrameGround(std::span<const Eigen::Vector3f> points_L, const Isometry3d& T_W_L, const FrameGroundParams& params = {});

  [[nodiscard]] bool empty() const { return lowest_.empty(); }
  // p_W's height above the ground nearby; NaN outside the grid or where no return is near.
  [[nodiscard]] float heightAbove(const Eigen::Vector3f& p_W) const;

 private:
  FrameGroundParams params_;
  int side_ = 0;
  Eigen::Matrix3f R_L_W_ = Eigen::Matrix3f::Identity();
  Eigen::Vector3f t_L_W_ = Eigen::Vector3f::Zero();
  std::vector<float> lowest_;  // per cell (row-major in y then x), +inf where none
};

}  // namespace artemis::mapping
