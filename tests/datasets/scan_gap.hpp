#pragma once
// How well two posed scans agree in the world frame.

#include "artemis/core/point_cloud.hpp"

namespace artemis::datasets::test_util {

// Median distance from every 10th non-ground point of `b` (within 30 m of its sensor, z above
// -1.2 m in the LiDAR frame) to its nearest neighbour in `a`, both moved into the world frame.
double medianGap(const PointCloud& a, const Isometry3d& T_W_A, const PointCloud& b, const Isometry3d& T_W_B);

}  // namespace artemis::datasets::test_util
