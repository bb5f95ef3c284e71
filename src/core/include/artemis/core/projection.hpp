#pragma once
// Projection of LiDAR points into a camera image with their depth.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/core/image.hpp"

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

// The frame's LiDAR depth as the camera sees it, for the per-frame stages (single precision,
// PinholeProjector; pixel centres at integer coordinates): each point that lands in a width x
// height image with its nearest pixel and depth, and per pixel the nearest point's depth (+inf
// where no point lands).
struct DepthProjection {
  struct Point {
    std::uint32_t index;  // into the scan
    std::uint32_t pixel;  // v * width + u
    float depth;
  };
  std::vector<Point> points;
  ImageF32 nearest;
};
// Fills `out`, reusing its storage.
void projectDepth(const PointCloud& points_L, const CameraView& view, int width, int height, DepthProjection& out);

// Each pixel becomes the least value of the (2 r + 1) x (2 r + 1) window around it (clipped at the
// borders), in two separable passes. One channel, no NaN (which of them would win is not defined).
void minFilter(ImageF32& image, int r);

}  // namespace artemis
