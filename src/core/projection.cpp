#include "artemis/core/projection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace artemis {

ProjectedPoints projectIntoCamera(const PointCloud& points_L, const CameraView& view) {
  ProjectedPoints out;
  const Eigen::Isometry3d T_C_L = view.T_L_C.inverse();
  const Eigen::Matrix3f R = T_C_L.linear().cast<float>();
  const Eigen::Vector3f t = T_C_L.translation().cast<float>();
  for (std::size_t i = 0; i < points_L.size(); ++i) {
    const Eigen::Vector3d p_C = (R * points_L.points[i] + t).cast<double>();
    const auto uv = view.camera.project(p_C);
    if (!uv || !view.camera.inImage(*uv)) continue;
    out.index.push_back(static_cast<std::uint32_t>(i));
    out.uv_px.push_back(uv->cast<float>());
    out.depth_m.push_back(static_cast<float>(p_C.z()));
  }
  return out;
}

void projectDepth(const PointCloud& points_L, const CameraView& view, int width, int height, DepthProjection& out) {
  out.points.clear();
  constexpr float kFar = std::numeric_limits<float>::infinity();
  if (out.nearest.width() == width && out.nearest.height() == height && out.nearest.channels() == 1) {
    std::fill(out.nearest.data().begin(), out.nearest.data().end(), kFar);
  } else {
    out.nearest = ImageF32(width, height, 1, kFar);
  }
  const Eigen::Isometry3d T_C_L = view.T_L_C.inverse();
  const Eigen::Matrix3f R = T_C_L.linear().cast<float>();
  const Eigen::Vector3f t = T_C_L.translation().cast<float>();
  const PinholeProjector project(view.camera);
  std::vector<float>& nearest = out.nearest.data();
  for (std::size_t i = 0; i < points_L.size(); ++i) {
    const Eigen::Vector3f p_C = R * points_L.points[i] + t;
    if (!(p_C.z() > static_cast<float>(PinholeCamera::kMinDepthM))) continue;
    const Eigen::Vector2f uv = project(p_C);
    const float u = uv.x();
    const float v = uv.y();
    if (!(u >= -0.5f && v >= -0.5f && u < static_cast<float>(width) - 0.5f && v < static_cast<float>(height) - 0.5f)) {
      continue;
    }
    const auto pixel = static_cast<std::size_t>(std::floor(v + 0.5f)) * static_cast<std::size_t>(width) +
                       static_cast<std::size_t>(std::floor(u + 0.5f));
    out.points.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(pixel), p_C.z()});
    nearest[pixel] = std::min(nearest[pixel], p_C.z());
  }
}

void minFilter(ImageF32& image, int r) {
  if (r <= 0 || image.empty()) return;
  const int w = image.width();
  const int h = image.height();
  std::vector<float> line(static_cast<std::size_t>(std::max(w, h)));
  // One pass along a line of n values `stride` apart, starting at `first`.
  const auto pass = [&](float* first, int n, std::size_t stride) {
    for (int k = 0; k < n; ++k) line[static_cast<std::size_t>(k)] = first[static_cast<std::size_t>(k) * stride];
    for (int k = 0; k < n; ++k) {
      const auto lo = line.begin() + std::max(0, k - r);
      const auto hi = line.begin() + std::min(n - 1, k + r) + 1;
      first[static_cast<std::size_t>(k) * stride] = *std::min_element(lo, hi);
    }
  };
  float* data = image.data().data();
  for (int v = 0; v < h; ++v) pass(data + static_cast<std::size_t>(v) * static_cast<std::size_t>(w), w, 1);
  for (int u = 0; u < w; ++u) pass(data + u, h, static_cast<std::size_t>(w));
}

}  // namespace artemis
