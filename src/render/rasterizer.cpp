#include "artemis/render/rasterizer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace artemis::render {

namespace {

constexpr int kStripRows = 16;
// Faces at least this many pixels wide are drawn row span by row span (RowSpans); narrower ones
// test every pixel of their box, which costs less than finding the span.
constexpr int kSpanMinWidth = 4;

// A face in screen space: pixel coordinates, 1/z at each corner, and its pixel bounds.
struct ScreenFace {
  std::uint32_t id = kNoFace;
  Eigen::Vector2f p[3];
  float inv_z[3] = {0, 0, 0};
  int u0 = 0, v0 = 0, u1 = -1, v1 = -1;  // inclusive
};

// Projects every face (in parallel); those off screen or out of the depth range keep id kNoFace.
void projectFaces(const MeshArrays& mesh, const View& view, std::span<const std::uint32_t> faces,
                  std::vector<ScreenFace>& screen) {
  const int w = view.camera.width_px;
  const int h = view.camera.height_px;
  const Isometry3d T_C_W = view.T_W_C.inverse();
  const Eigen::Matrix3f R = T_C_W.linear().cast<float>();
  const Eigen::Vector3f t = T_C_W.translation().cast<float>();
  const PinholeProjector project(view.camera);
  const auto near = static_cast<float>(view.near_m);
  const auto far = static_cast<float>(view.far_m);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, screen.size(), 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const std::uint32_t id = faces.empty() ? static_cast<std::uint32_t>(k) : faces[k];
      ScreenFace& s = screen[k];
      s.id = kNoFace;
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
}

// The faces of each strip of rows, in face order (counting sort): strip b's are
// binned[start[b] .. start[b + 1]).
struct Bins {
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> binned;
};

Bins binFaces(const std::vector<ScreenFace>& screen, int strips) {
  Bins bins;
  bins.start.assign(static_cast<std::size_t>(strips) + 1, 0);
  for (const ScreenFace& s : screen) {
    if (s.id == kNoFace) continue;
    for (int b = s.v0 / kStripRows; b <= s.v1 / kStripRows; ++b) ++bins.start[static_cast<std::size_t>(b) + 1];
  }
  for (int b = 0; b < strips; ++b)
    bins.start[static_cast<std::size_t>(b) + 1] += bins.start[static_cast<std::size_t>(b)];
  bins.binned.resize(bins.start.back());
  std::vector<std::uint32_t> fill(bins.start.begin(), bins.start.end() - 1);
  for (std::size_t k = 0; k < screen.size(); ++k) {
    const ScreenFace& s = screen[k];
    if (s.id == kNoFace) continue;
    for (int b = s.v0 / kStripRows; b <= s.v1 / kStripRows; ++b) {
      bins.binned[fill[static_cast<std::size_t>(b)]++] = static_cast<std::uint32_t>(k);
    }
  }
  return bins;
}

// Which pixels of a row can pass drawFace's test, without testing the others. drawFace computes
// each barycentric weight from an edge function E_i(u, v) = A_i u + D_i v + C_i of the face's
// float corners, in float; here the same functions are exact (double, from the same floats). In a
// box of W x H pixels around the face every product drawFace forms is at most W H and the weights
// it compares are at most a few times 1 + |E| / |area|, so its rounding moves E_i by less than
// kSlack eps W H (generously: the analysis gives ~40). A pixel whose exact E_i has the wrong sign
// by more than that fails in float too, so only the span between the roots of E_i = -+slack is
// tested, and the picture stays exactly what testing the whole box gives.
class RowSpans {
 public:
  explicit RowSpans(const ScreenFace& s) {
    const double ax = s.p[0].x(), ay = s.p[0].y(), bx = s.p[1].x(), by = s.p[1].y(), cx = s.p[2].x(), cy = s.p[2].y();
    const double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    a_ = {by - cy, cy - ay, ay - by};
    d_ = {cx - bx, ax - cx, bx - ax};
    c_[0] = bx * cy - by * cx;
    c_[1] = cx * ay - cy * ax;
    c_[2] = area - c_[0] - c_[1];
    const double width = std::max({ax, bx, cx}) - std::min({ax, bx, cx});
    const double height = std::max({ay, by, cy}) - std::min({ay, by, cy});
    constexpr double kSlack = 64.0 * std::numeric_limits<float>::epsilon();
    // The double products of far off-screen corners round too (relative 1e-16).
    const double farthest =
        std::max({std::abs(ax), std::abs(ay), std::abs(bx), std::abs(by), std::abs(cx), std::abs(cy)});
    slack_ = kSlack * (width + 1.0) * (height + 1.0) + 1e-12 * farthest * farthest;
    // drawFace's weights are E_i / area with the area as drawFace computes it (float): its sign.
    const float af =
        (s.p[1].x() - s.p[0].x()) * (s.p[2].y() - s.p[0].y()) - (s.p[1].y() - s.p[0].y()) * (s.p[2].x() - s.p[0].x());
    sign_ = af > 0.0f ? 1.0 : -1.0;
  }

  // Narrows [first, last] to row v's candidates; false when none is left.
  bool narrow(int v, int& first, int& last) const {
    double lo = first;
    double hi = last;
    for (std::size_t i = 0; i < 3; ++i) {
      const double a = sign_ * a_[i];
      const double rest = sign_ * (d_[i] * v + c_[i]);  // weight i >= 0 needs a u + rest >= -slack (about)
      if (a == 0.0) {
        if (rest < -slack_) return false;
        continue;
      }
      const double root = -rest / a;
      const double reach = slack_ / std::abs(a) + 1e-6;
      if (a > 0.0) {
        lo = std::max(lo, root - reach);
      } else {
        hi = std::min(hi, root + reach);
      }
    }
    if (!(lo <= hi)) return false;
    first = static_cast<int>(std::ceil(lo));
    last = static_cast<int>(std::floor(hi));
    return first <= last;
  }

 private:
  std::array<double, 3> a_{}, d_{}, c_{};
  double slack_ = 0.0;
  double sign_ = 1.0;
};

// Draws face s's pixels in rows [row0, row1]: barycentric weights of each pixel centre (signs
// follow the face's winding), nearest depth wins, ties to the lower face id.
void drawFace(const ScreenFace& s, int row0, int row1, const MeshArrays& mesh, bool coloured, Picture& out) {
  const int w = out.depth.width();
  const Eigen::Vector2f& a = s.p[0];
  const Eigen::Vector2f& b = s.p[1];
  const Eigen::Vector2f& c = s.p[2];
  const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  if (!(std::abs(area) > 1e-12f)) return;  // degenerate on screen
  const float inv_area = 1.0f / area;
  std::optional<RowSpans> spans;
  if (s.u1 - s.u0 + 1 >= kSpanMinWidth) spans.emplace(s);
  for (int v = std::max(s.v0, row0); v <= std::min(s.v1, row1); ++v) {
    int first = s.u0;
    int last = s.u1;
    if (spans && !spans->narrow(v, first, last)) continue;
    first = std::max(first, s.u0);
    last = std::min(last, s.u1);
    for (int u = first; u <= last; ++u) {
      const Eigen::Vector2f q(static_cast<float>(u), static_cast<float>(v));
      const float w0 = ((b.x() - q.x()) * (c.y() - q.y()) - (b.y() - q.y()) * (c.x() - q.x())) * inv_area;
      const float w1 = ((c.x() - q.x()) * (a.y() - q.y()) - (c.y() - q.y()) * (a.x() - q.x())) * inv_area;
      const float w2 = 1.0f - w0 - w1;
      if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
      const float inv_z = w0 * s.inv_z[0] + w1 * s.inv_z[1] + w2 * s.inv_z[2];
      const float z = 1.0f / inv_z;
      float& depth = out.depth.at(u, v);
      const std::size_t pixel = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u);
      if (z > depth || (z == depth && s.id > out.face[pixel])) continue;
      depth = z;
      out.face[pixel] = s.id;
      if (coloured) {
        // Perspective-correct: weights by 1/z, renormalised.
        const auto& tri = mesh.triangles[s.id];
        const float k0 = w0 * s.inv_z[0] * z;
        const float k1 = w1 * s.inv_z[1] * z;
        const float k2 = w2 * s.inv_z[2] * z;
        const Eigen::Vector3f col = k0 * mesh.colours[tri[0]] + k1 * mesh.colours[tri[1]] + k2 * mesh.colours[tri[2]];
        for (int ch = 0; ch < 3; ++ch) out.colour.at(u, v, ch) = col(ch);
      }
    }
  }
}

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

  // Kept between calls on this thread: a fresh array would be paged in every picture. (A named
  // reference: inside the tasks below, the thread_local's own name would mean their thread's.)
  thread_local std::vector<ScreenFace> kept;
  std::vector<ScreenFace>& screen = kept;
  screen.resize(faces.empty() ? mesh.triangles.size() : faces.size());
  projectFaces(mesh, view, faces, screen);
  const int strips = (h + kStripRows - 1) / kStripRows;
  const Bins bins = binFaces(screen, strips);
  // Each strip draws its faces' pixels in its rows: one thread writes each pixel.
  tbb::parallel_for(tbb::blocked_range<int>(0, strips, 1), [&](const auto& range) {
    for (int b = range.begin(); b < range.end(); ++b) {
      const int row0 = b * kStripRows;
      const int row1 = std::min(h - 1, row0 + kStripRows - 1);
      for (std::uint32_t j = bins.start[static_cast<std::size_t>(b)]; j < bins.start[static_cast<std::size_t>(b) + 1];
           ++j) {
        drawFace(screen[bins.binned[j]], row0, row1, mesh, coloured, out);
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
