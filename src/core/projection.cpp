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
  const auto row_size = static_cast<std::size_t>(w);
  float* data = image.data().data();
  const auto row = [&](int v) { return data + static_cast<std::size_t>(v) * row_size; };
  // Along each row, in place, from a copy of the row: the least with each shift in turn, whole
  // rows at a time (loops the compiler vectorises; a window loop per pixel does not).
  std::vector<float> line(row_size);
  for (int v = 0; v < h; ++v) {
    std::copy_n(row(v), row_size, line.data());
    float* out = row(v);
    const float* in = line.data();
    for (std::size_t s = 1; s <= static_cast<std::size_t>(r) && s < row_size; ++s) {
      for (std::size_t u = 0; u + s < row_size; ++u) out[u] = std::min(out[u], in[u + s]);
      for (std::size_t u = s; u < row_size; ++u) out[u] = std::min(out[u], in[u - s]);
    }
  }
  // Down the columns a whole row at a time, in memory order (a pass down each column would touch a
  // new cache line at every step). The rows above, already overwritten, come from a ring of copies.
  std::vector<float> above(static_cast<std::size_t>(r) * row_size);
  const auto saved = [&](int v) { return above.data() + static_cast<std::size_t>(v % r) * row_size; };
  for (int v = 0; v < h; ++v) {
    std::copy_n(row(v), row_size, line.data());
    float* out = row(v);
    for (int k = std::max(0, v - r); k < v; ++k) {
      const float* in = saved(k);
      for (std::size_t u = 0; u < row_size; ++u) out[u] = std::min(out[u], in[u]);
    }
    for (int k = v + 1; k <= std::min(h - 1, v + r); ++k) {
      const float* in = row(k);
      for (std::size_t u = 0; u < row_size; ++u) out[u] = std::min(out[u], in[u]);
    }
    std::copy_n(line.data(), row_size, saved(v));
  }
}

}  // namespace artemis
