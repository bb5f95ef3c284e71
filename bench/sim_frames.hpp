#pragma once
// The simulated street's scans as the pipeline reads them, for the benchmarks.

#include "artemis/core/point_cloud.hpp"
#include "artemis/sim/simulator.hpp"

namespace artemis::bench {

// The scan's points within the dataset readers' default range gate (2-70 m).
inline PointCloud rangeGated(const sim::LidarScan& scan) {
  PointCloud cloud;
  for (const auto& p : scan.points_L) {
    const float r = p.head<3>().norm();
    if (r >= 2.0f && r <= 70.0f) cloud.points.push_back(p.head<3>());
  }
  return cloud;
}

}  // namespace artemis::bench
