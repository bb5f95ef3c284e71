#pragma once
// Projection of LiDAR points into a camera image with their depth.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "artemis/core/frame.hpp"

namespace artemis {

struct ProjectedPoints {
  std::vector<std::uint32_t> index;  // index of the point in the scan
  std::vector<Eigen::Vector2f> uv_px;
  std::vector<float> depth_m;  // z in the camera frame, > 0
  [[nodiscard]] std::size_t size() const { return index.size(); }
};

// The points of `points_L` that land inside `view`'s image, with pixel coordinates and depth.
// Points behind the camera (depth <= PinholeCamera::kMinDepthM) are rejected, never mirrored in.
ProjectedPoints projectIntoCamera(const PointCloud& points_L, const CameraView& view);

}  // namespace artemis
