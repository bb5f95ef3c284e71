#include "artemis/render/highlight.hpp"

#include <algorithm>
#include <cmath>

namespace artemis::render {

namespace {

// Saturated colours away from SemanticKITTI's road, sidewalk, building and vegetation colours.
constexpr std::array<Rgb8, kHighlightColours> kPalette = {{
    {255, 214, 0},   // yellow
    {255, 0, 200},   // magenta
    {0, 230, 255},   // cyan
    {255, 96, 0},    // orange
    {120, 255, 0},   // lime
    {160, 80, 255},  // violet
}};

std::uint8_t toByte(float x) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

Rgb8 highlightColour(std::size_t k) {
  return kPalette[k % kHighlightColours];
}

std::vector<std::uint8_t> vertexHighlight(std::span<const std::uint8_t> vertex_class,
                                          std::span<const std::uint8_t> classes) {
  std::array<std::uint8_t, 256> rank{};  // class id -> 1 + position in `classes`, 0 when absent
  for (std::size_t k = classes.size(); k-- > 0;) {
    rank[classes[k]] = static_cast<std::uint8_t>(std::min<std::size_t>(k + 1, 255));
  }
  std::vector<std::uint8_t> out(vertex_class.size());
  std::transform(vertex_class.begin(), vertex_class.end(), out.begin(), [&](std::uint8_t c) { return rank[c]; });
  return out;
}

ShadedPicture shade(const MeshArrays& mesh, const Picture& picture, const View& view,
                    std::span<const std::uint8_t> vertex_highlight, const ShadeParams& params) {
  const int w = picture.depth.width();
  const int h = picture.depth.height();
  ShadedPicture out;
  out.image = ImageU8(w, h, 3, 0);
  out.mask = ImageU8(w, h, 1, 0);
  const bool textured = picture.colour.channels() == 3;
  const Eigen::Vector3f eye = view.T_W_C.translation().cast<float>();
  const float hw = std::clamp(params.highlight_weight, 0.0f, 1.0f);
  const Isometry3d T_C_W = view.T_W_C.inverse();
  const Eigen::Matrix3f R = T_C_W.linear().cast<float>();
  const Eigen::Vector3f t = T_C_W.translation().cast<float>();
  const PinholeProjector project(view.camera);
  // The highlight of pixel (u, v) on face f: that of the face's vertex nearest to the pixel.
  const auto highlight_at = [&](std::uint32_t f, int u, int v) -> std::uint8_t {
    const auto& tri = mesh.triangles[f];
    const std::size_t n = vertex_highlight.size();
    if (tri[0] >= n || tri[1] >= n || tri[2] >= n) return 0;
    const std::uint8_t hv[3] = {vertex_highlight[tri[0]], vertex_highlight[tri[1]], vertex_highlight[tri[2]]};
    if (hv[0] == hv[1] && hv[1] == hv[2]) return hv[0];
    Eigen::Vector2f p[3];
    for (int c = 0; c < 3; ++c) p[c] = project(R * mesh.positions[tri[static_cast<std::size_t>(c)]] + t);
    const Eigen::Vector2f q(static_cast<float>(u), static_cast<float>(v));
    const auto cross = [](const Eigen::Vector2f& a, const Eigen::Vector2f& b) { return a.x() * b.y() - a.y() * b.x(); };
    // Unnormalised barycentric weights: the area opposite each corner (same sign inside the face).
    const float weight[3] = {std::abs(cross(p[1] - q, p[2] - q)), std::abs(cross(p[2] - q, p[0] - q)),
                             std::abs(cross(p[0] - q, p[1] - q))};
    const int best = weight[0] >= weight[1] ? (weight[0] >= weight[2] ? 0 : 2) : (weight[1] >= weight[2] ? 1 : 2);
    return hv[best];
  };
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const std::uint32_t f = picture.faceAt(u, v);
      if (f == kNoFace || f >= mesh.triangles.size()) {
        for (int c = 0; c < 3; ++c) out.image.at(u, v, c) = params.background[static_cast<std::size_t>(c)];
        continue;
      }
      ++out.covered_pixels;
      Eigen::Vector3f colour;
      if (textured) {
        colour = {picture.colour.at(u, v, 0), picture.colour.at(u, v, 1), picture.colour.at(u, v, 2)};
      } else {
        const auto& corners = mesh.triangles[f];
        const Eigen::Vector3f& a = mesh.positions[corners[0]];
        const Eigen::Vector3f n = (mesh.positions[corners[1]] - a).cross(mesh.positions[corners[2]] - a);
        const Eigen::Vector3f ray = a - eye;
        const float denom = n.norm() * ray.norm();
        const float cosine = denom > 0.0f ? std::abs(n.dot(ray)) / denom : 1.0f;
        const float k = params.ambient + (1.0f - params.ambient) * cosine;
        colour = Eigen::Vector3f(params.untextured[0], params.untextured[1], params.untextured[2]) * (k / 255.0f);
      }
      const std::uint8_t hl = vertex_highlight.empty() ? 0 : highlight_at(f, u, v);
      if (hl != 0) {
        const Rgb8 c = highlightColour(static_cast<std::size_t>(hl) - 1);
        colour = (1.0f - hw) * colour + hw * Eigen::Vector3f(c[0], c[1], c[2]) / 255.0f;
        out.mask.at(u, v) = 255;
        ++out.highlighted_pixels;
      }
      for (int c = 0; c < 3; ++c) out.image.at(u, v, c) = toByte(colour(c));
    }
  }
  return out;
}

}  // namespace artemis::render
