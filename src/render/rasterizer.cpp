#include "artemis/render/rasterizer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace artemis::render {

namespace {

constexpr int kStripRows = 16;

// A face in screen space: pixel coordinates, 1/z at each corner, and its pixel bounds.
struct ScreenFace {
  std::uint32_t id = kNoFace;
  Eigen::Vector2f p[3];
  float inv_z[3] = {0, 0, 0};
  int u0 = 0, v0 = 0, u1 = -1, v1 = -1;  // inclusive
};

}  // namespace

Picture rasterize(const MeshArrays& mesh, const View& view, std::span<const std::uint32_t> faces) {
  const int w = view.camera.width_px;
  const int h = view.camera.height_px;
  Picture out;
  out.depth = ImageF32(w, h, 1, std::numeric_limits<float>::infinity());
  out.face.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kNoFace);
  const bool coloured = !mesh.colours.empty() && mesh.colours.size() == mesh.positions.size();
  if (coloured) out.colour = ImageF32(w, h, 3, 0.0f);
  if (w <= 0 || h <= 0) return out;

  const std::size_t n = faces.empty() ? mesh.triangles.size() : faces.size();
  const Isometry3d T_C_W = view.T_W_C.inverse();
  const Eigen::Matrix3f R = T_C_W.linear().cast<float>();
  const Eigen::Vector3f t = T_C_W.translation().cast<float>();
  const PinholeProjector project(view.camera);
  const auto near = static_cast<float>(view.near_m);
  const auto far = static_cast<float>(view.far_m);

  // 1. Project every face (in parallel); those off screen or out of the depth range drop out.
  std::vector<ScreenFace> screen(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const std::uint32_t id = faces.empty() ? static_cast<std::uint32_t>(k) : faces[k];
      ScreenFace& s = screen[k];
      if (id >= mesh.triangles.size()) continue;
      const auto& tri = mesh.triangles[id];
      bool ok = true;
      for (int c = 0; c < 3 && ok; ++c) {
        if (tri[static_cast<std::size_t>(c)] >= mesh.positions.size()) {
          ok = false;
          break;
        }
        const Eigen::Vector3f p_C = R * mesh.positions[tri[static_cast<std::size_t>(c)]] + t;
        if (!(p_C.z() >= near && p_C.z() <= far)) {  // also false for NaN
          ok = false;
          break;
        }
        s.inv_z[c] = 1.0f / p_C.z();
        s.p[c] = project(p_C);
      }
      if (!ok) continue;
      const float lo_u = std::min({s.p[0].x(), s.p[1].x(), s.p[2].x()});
      const float hi_u = std::max({s.p[0].x(), s.p[1].x(), s.p[2].x()});
      const float lo_v = std::min({s.p[0].y(), s.p[1].y(), s.p[2].y()});
      const float hi_v = std::max({s.p[0].y(), s.p[1].y(), s.p[2].y()});
      if (!(hi_u >= 0.0f && lo_u <= static_cast<float>(w - 1) && hi_v >= 0.0f && lo_v <= static_cast<float>(h - 1))) {
        continue;
      }
      s.u0 = std::max(0, static_cast<int>(std::ceil(lo_u)));
      s.u1 = std::min(w - 1, static_cast<int>(std::floor(hi_u)));
      s.v0 = std::max(0, static_cast<int>(std::ceil(lo_v)));
      s.v1 = std::min(h - 1, static_cast<int>(std::floor(hi_v)));
      if (s.u0 > s.u1 || s.v0 > s.v1) continue;  // covers no pixel centre
      s.id = id;
    }
  });

  // 2. Bin faces into strips of rows (counting sort, in face order).
  const int strips = (h + kStripRows - 1) / kStripRows;
  std::vector<std::uint32_t> start(static_cast<std::size_t>(strips) + 1, 0);
  for (const ScreenFace& s : screen) {
    if (s.id == kNoFace) continue;
    for (int b = s.v0 / kStripRows; b <= s.v1 / kStripRows; ++b) ++start[static_cast<std::size_t>(b) + 1];
  }
  for (int b = 0; b < strips; ++b) start[static_cast<std::size_t>(b) + 1] += start[static_cast<std::size_t>(b)];
  std::vector<std::uint32_t> binned(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < screen.size(); ++k) {
    const ScreenFace& s = screen[k];
    if (s.id == kNoFace) continue;
    for (int b = s.v0 / kStripRows; b <= s.v1 / kStripRows; ++b) {
      binned[fill[static_cast<std::size_t>(b)]++] = static_cast<std::uint32_t>(k);
    }
  }

  // 3. Each strip draws its faces' pixels in its rows: edge functions, nearest depth wins.
  tbb::parallel_for(tbb::blocked_range<int>(0, strips, 1), [&](const auto& range) {
    for (int b = range.begin(); b < range.end(); ++b) {
      const int row0 = b * kStripRows;
      const int row1 = std::min(h - 1, row0 + kStripRows - 1);
      for (std::uint32_t j = start[static_cast<std::size_t>(b)]; j < start[static_cast<std::size_t>(b) + 1]; ++j) {
        const ScreenFace& s = screen[binned[j]];
        const Eigen::Vector2f& a = s.p[0];
        const Eigen::Vector2f& bb = s.p[1];
        const Eigen::Vector2f& c = s.p[2];
        const float area = (bb.x() - a.x()) * (c.y() - a.y()) - (bb.y() - a.y()) * (c.x() - a.x());
        if (!(std::abs(area) > 1e-12f)) continue;  // degenerate on screen
        const float inv_area = 1.0f / area;
        for (int v = std::max(s.v0, row0); v <= std::min(s.v1, row1); ++v) {
          for (int u = s.u0; u <= s.u1; ++u) {
            const Eigen::Vector2f q(static_cast<float>(u), static_cast<float>(v));
            // Barycentric weights of the pixel centre (signs follow the face's winding).
            const float w0 = ((bb.x() - q.x()) * (c.y() - q.y()) - (bb.y() - q.y()) * (c.x() - q.x())) * inv_area;
            const float w1 = ((c.x() - q.x()) * (a.y() - q.y()) - (c.y() - q.y()) * (a.x() - q.x())) * inv_area;
            const float w2 = 1.0f - w0 - w1;
            if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
            const float inv_z = w0 * s.inv_z[0] + w1 * s.inv_z[1] + w2 * s.inv_z[2];
            const float z = 1.0f / inv_z;
            float& depth = out.depth.at(u, v);
            const std::size_t pixel =
                static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u);
            if (z > depth || (z == depth && s.id > out.face[pixel])) continue;
            depth = z;
            out.face[pixel] = s.id;
            if (coloured) {
              // Perspective-correct: weights by 1/z, renormalised.
              const auto& tri = mesh.triangles[s.id];
              const float k0 = w0 * s.inv_z[0] * z;
              const float k1 = w1 * s.inv_z[1] * z;
              const float k2 = w2 * s.inv_z[2] * z;
              const Eigen::Vector3f col =
                  k0 * mesh.colours[tri[0]] + k1 * mesh.colours[tri[1]] + k2 * mesh.colours[tri[2]];
              for (int ch = 0; ch < 3; ++ch) out.colour.at(u, v, ch) = col(ch);
            }
          }
        }
      }
    }
  });
  return out;
}

Picture splat(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> colours, double radius_m,
              const View& view) {
  const int w = view.camera.width_px;
  const int h = view.camera.height_px;
  Picture out;
  out.depth = ImageF32(w, h, 1, std::numeric_limits<float>::infinity());
  out.face.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kNoFace);
  const bool coloured = colours.size() == points.size() && !points.empty();
  if (coloured) out.colour = ImageF32(w, h, 3, 0.0f);
  const Isometry3d T_C_W = view.T_W_C.inverse();
  const Eigen::Matrix3f R = T_C_W.linear().cast<float>();
  const Eigen::Vector3f t = T_C_W.translation().cast<float>();
  const PinholeProjector project(view.camera);
  const auto r = static_cast<float>(radius_m);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = R * points[i] + t;
    if (!(p.z() >= static_cast<float>(view.near_m) && p.z() <= static_cast<float>(view.far_m))) continue;
    const Eigen::Vector2f uv = project(p);
    const float u = uv.x();
    const float v = uv.y();
    const float rad = std::max(0.5f, project.fx * r / p.z());
    const int u0 = std::max(0, static_cast<int>(std::ceil(u - rad)));
    const int u1 = std::min(w - 1, static_cast<int>(std::floor(u + rad)));
    const int v0 = std::max(0, static_cast<int>(std::ceil(v - rad)));
    const int v1 = std::min(h - 1, static_cast<int>(std::floor(v + rad)));
    for (int y = v0; y <= v1; ++y) {
      for (int x = u0; x <= u1; ++x) {
        const float du = static_cast<float>(x) - u;
        const float dv = static_cast<float>(y) - v;
        if (du * du + dv * dv > rad * rad) continue;
        float& depth = out.depth.at(x, y);
        if (p.z() >= depth) continue;
        depth = p.z();
        out.face[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
            static_cast<std::uint32_t>(i);
        if (coloured) {
          for (int ch = 0; ch < 3; ++ch) out.colour.at(x, y, ch) = colours[i](ch);
        }
      }
    }
  }
  return out;
}

}  // namespace artemis::render
