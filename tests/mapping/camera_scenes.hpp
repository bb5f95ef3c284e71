#pragma once
// Scenes for the semantic fusion and refinement tests: a camera at the LiDAR's origin and walls
// of points in front of it.

#include "artemis/core/frame.hpp"
#include "artemis/core/point_cloud.hpp"

namespace artemis::mapping::test {

// A 200 x 100 camera at the LiDAR's origin looking along +x (KITTI's mounting).
inline CameraView forwardCamera() {
  CameraView view;
  view.name = "image_02";
  view.camera = {200, 100, 100.0, 100.0, 99.5, 49.5};
  Eigen::Matrix3d R_L_C;
  R_L_C << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  view.T_L_C.linear() = R_L_C;
  return view;
}

// Points on the plane x = `x`, y in [-half_y, half_y], z in [-half_z, half_z], 0.05 m apart, offset
// so that every 0.1 m cell holds exactly 2 x 2 of them.
inline PointCloud wall(float x, float half_y, float half_z) {
  PointCloud cloud;
  for (float y = -half_y + 0.025f; y < half_y; y += 0.05f) {
    for (float z = -half_z + 0.025f; z < half_z; z += 0.05f) cloud.points.emplace_back(x, y, z);
  }
  return cloud;
}

}  // namespace artemis::mapping::test
