// The rasterizer against pictures whose answers are known: a square at a known depth, occlusion,
// perspective-correct colour, faces behind the camera, broken input, thread-count independence,
// and the same pixels as testing every pixel of every face's box.
#include "artemis/render/rasterizer.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace artemis::render {
namespace {

// A 200 x 100 camera at the origin looking along the world's +z (world = camera frame).
View view() {
  View v;
  v.camera = {200, 100, 100.0, 100.0, 99.5, 49.5};
  return v;
}

// A square of half-size `half` facing the camera at depth z, centred on (x, y): two triangles.
void addSquare(std::vector<Eigen::Vector3f>& p, std::vector<std::array<std::uint32_t, 3>>& t, float x, float y, float z,
               float half) {
  const auto b = static_cast<std::uint32_t>(p.size());
  p.insert(p.end(),
           {{x - half, y - half, z}, {x + half, y - half, z}, {x + half, y + half, z}, {x - half, y + half, z}});
  t.push_back({b, b + 1, b + 2});
  t.push_back({b, b + 2, b + 3});
}

TEST(Rasterizer, SquareAtKnownDepthCoversItsProjection) {
  std::vector<Eigen::Vector3f> p;
  std::vector<std::array<std::uint32_t, 3>> t;
  addSquare(p, t, 0.0f, 0.0f, 5.0f, 1.0f);  // projects to u, v in cx, cy +- 20 px
  const Picture pic = rasterize({p, t, {}}, view());
  int covered = 0;
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 200; ++u) {
      const bool inside = std::abs(u - 99.5) < 20.0 && std::abs(v - 49.5) < 20.0;
      const bool drawn = pic.faceAt(u, v) != kNoFace;
      EXPECT_EQ(drawn, inside) << u << "," << v;
      if (drawn) {
        EXPECT_NEAR(pic.depth.at(u, v), 5.0f, 1e-4f);
        ++covered;
      } else {
        EXPECT_TRUE(std::isinf(pic.depth.at(u, v)));
      }
    }
  }
  EXPECT_EQ(covered, 40 * 40);
  EXPECT_TRUE(pic.colour.empty());
}

TEST(Rasterizer, TheNearerSurfaceWinsWhateverTheOrder) {
  for (const bool near_first : {true, false}) {
    std::vector<Eigen::Vector3f> p;
    std::vector<std::array<std::uint32_t, 3>> t;
    if (near_first) addSquare(p, t, 0.0f, 0.0f, 4.0f, 0.5f);
    addSquare(p, t, 0.0f, 0.0f, 10.0f, 4.0f);
    if (!near_first) addSquare(p, t, 0.0f, 0.0f, 4.0f, 0.5f);
    const Picture pic = rasterize({p, t, {}}, view());
    EXPECT_NEAR(pic.depth.at(100, 50), 4.0f, 1e-4f);
    EXPECT_NEAR(pic.depth.at(100 + 20, 50), 10.0f, 1e-4f);  // 0.2 m off axis at 10 m... outside the near one
    const std::uint32_t near_face = pic.faceAt(100, 50);
    EXPECT_EQ(near_face / 2, near_first ? 0u : 1u);
  }
}

TEST(Rasterizer, ColourIsInterpolatedPerspectiveCorrectly) {
  // A floor-like face receding in depth: its colour goes from red (near) to blue (far). At the
  // pixel of the point halfway in 3-D the colour must be the average, not skewed to the near end.
  std::vector<Eigen::Vector3f> p{{-2.0f, 1.0f, 2.0f}, {2.0f, 1.0f, 2.0f}, {2.0f, 1.0f, 10.0f}, {-2.0f, 1.0f, 10.0f}};
  std::vector<std::array<std::uint32_t, 3>> t{{0, 1, 2}, {0, 2, 3}};
  std::vector<Eigen::Vector3f> c{{1, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}};
  const Picture pic = rasterize({p, t, c}, view());
  ASSERT_FALSE(pic.colour.empty());
  // The midpoint (0, 1, 6) projects to v = 100 / 6 + 49.5 = 66.17; take the row with v = 66 and
  // compare with the colour expected at that pixel's own depth.
  const int v = 66;
  const float z = 100.0f * 1.0f / (static_cast<float>(v) - 49.5f);  // depth of the floor at row v
  const float s = (z - 2.0f) / 8.0f;                                // share of the way to the far edge
  EXPECT_NEAR(pic.depth.at(100, v), z, 1e-3f);
  EXPECT_NEAR(pic.colour.at(100, v, 0), 1.0f - s, 1e-3f);
  EXPECT_NEAR(pic.colour.at(100, v, 2), s, 1e-3f);
}

TEST(Rasterizer, FacesBehindTheCameraOrBrokenAreNotDrawn) {
  std::vector<Eigen::Vector3f> p;
  std::vector<std::array<std::uint32_t, 3>> t;
  addSquare(p, t, 0.0f, 0.0f, -5.0f, 1.0f);  // behind
  addSquare(p, t, 0.0f, 0.0f, 0.01f, 1.0f);  // closer than near_m
  p.push_back({std::nanf(""), 0.0f, 5.0f});
  t.push_back({0, 1, static_cast<std::uint32_t>(p.size() - 1)});  // a NaN vertex
  t.push_back({0, 1, 999});                                       // an index out of range
  const Picture pic = rasterize({p, t, {}}, view());
  for (const std::uint32_t f : pic.face) ASSERT_EQ(f, kNoFace);
  // A face subset: only the listed faces are drawn.
  addSquare(p, t, 0.0f, 0.0f, 5.0f, 1.0f);
  const std::vector<std::uint32_t> only{static_cast<std::uint32_t>(t.size() - 1)};
  const Picture some = rasterize({p, t, {}}, view(), only);
  std::size_t drawn = 0;
  for (const std::uint32_t f : some.face) {
    if (f != kNoFace) {
      ASSERT_EQ(f, only[0]);
      ++drawn;
    }
  }
  EXPECT_GT(drawn, 700u);  // half the square
}

TEST(Rasterizer, SamePictureOnOneAndTwoThreads) {
  std::vector<Eigen::Vector3f> p;
  std::vector<std::array<std::uint32_t, 3>> t;
  std::vector<Eigen::Vector3f> c;
  for (int k = 0; k < 400; ++k) {
    addSquare(p, t, 0.05f * static_cast<float>(k % 20) - 0.5f, 0.05f * static_cast<float>(k / 20) - 0.5f,
              3.0f + 0.01f * static_cast<float>(k % 7), 0.2f);
  }
  for (std::size_t i = 0; i < p.size(); ++i) c.emplace_back(static_cast<float>(i % 3), 0.5f, 0.25f);
  std::vector<Picture> pictures;
  for (const int threads : {1, 2}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    pictures.push_back(rasterize({p, t, c}, view()));
  }
  EXPECT_EQ(pictures[0].face, pictures[1].face);
  EXPECT_EQ(pictures[0].depth.data(), pictures[1].depth.data());
  EXPECT_EQ(pictures[0].colour.data(), pictures[1].colour.data());
}

// What the rasterizer promises pixel for pixel: every pixel centre of a face's box tested with
// the barycentric weights below, nearest depth winning, ties to the lower face. The rasterizer
// skips the pixels it can prove fail; the picture must not change.
Picture everyPixelOfEveryBox(const std::vector<Eigen::Vector3f>& p, const std::vector<std::array<std::uint32_t, 3>>& t,
                             const View& view) {
  const int w = view.camera.width_px;
  const int h = view.camera.height_px;
  Picture out;
  out.depth = ImageF32(w, h, 1, std::numeric_limits<float>::infinity());
  out.face.assign(static_cast<std::size_t>(w * h), kNoFace);
  const PinholeProjector project(view.camera);
  for (std::uint32_t id = 0; id < t.size(); ++id) {
    Eigen::Vector2f s[3];
    float inv_z[3];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3f& x = p[t[id][static_cast<std::size_t>(c)]];
      inv_z[c] = 1.0f / x.z();
      s[c] = project(x);
    }
    const float area = (s[1].x() - s[0].x()) * (s[2].y() - s[0].y()) - (s[1].y() - s[0].y()) * (s[2].x() - s[0].x());
    if (!(std::abs(area) > 1e-12f)) continue;
    const int u0 = std::max(0, static_cast<int>(std::ceil(std::min({s[0].x(), s[1].x(), s[2].x()}))));
    const int u1 = std::min(w - 1, static_cast<int>(std::floor(std::max({s[0].x(), s[1].x(), s[2].x()}))));
    const int v0 = std::max(0, static_cast<int>(std::ceil(std::min({s[0].y(), s[1].y(), s[2].y()}))));
    const int v1 = std::min(h - 1, static_cast<int>(std::floor(std::max({s[0].y(), s[1].y(), s[2].y()}))));
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) {
        const auto qx = static_cast<float>(u);
        const auto qy = static_cast<float>(v);
        const float w0 = ((s[1].x() - qx) * (s[2].y() - qy) - (s[1].y() - qy) * (s[2].x() - qx)) * (1.0f / area);
        const float w1 = ((s[2].x() - qx) * (s[0].y() - qy) - (s[2].y() - qy) * (s[0].x() - qx)) * (1.0f / area);
        const float w2 = 1.0f - w0 - w1;
        if (w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) continue;
        const float z = 1.0f / (w0 * inv_z[0] + w1 * inv_z[1] + w2 * inv_z[2]);
        const auto pixel = static_cast<std::size_t>(v * w + u);
        if (z > out.depth.at(u, v) || (z == out.depth.at(u, v) && id > out.face[pixel])) continue;
        out.depth.at(u, v) = z;
        out.face[pixel] = id;
      }
    }
  }
  return out;
}

TEST(Rasterizer, SkipsOnlyPixelsThatFailTheTest) {
  // Faces of every shape in front of the camera: small and large, slivers whose corners lie on a
  // line to within a rounding, and faces reaching far off screen (a corner just beyond near_m).
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> p;
  std::vector<std::array<std::uint32_t, 3>> t;
  for (int k = 0; k < 4000; ++k) {
    const float z = 0.5f + 20.0f * unit(random);
    const Eigen::Vector3f centre((unit(random) - 0.5f) * 2.4f * z, (unit(random) - 0.5f) * 1.2f * z, z);
    const float size = (k % 4 == 0 ? 0.5f : 0.05f) * z * unit(random);
    const auto b = static_cast<std::uint32_t>(p.size());
    for (int c = 0; c < 3; ++c) {
      p.push_back(centre + size * Eigen::Vector3f(unit(random) - 0.5f, unit(random) - 0.5f, 0.2f * unit(random)));
    }
    if (k % 5 == 1) p[b + 2] = p[b] + (p[b + 1] - p[b]) * 0.37f + Eigen::Vector3f(1e-6f, -1e-6f, 0.0f);  // sliver
    if (k % 50 == 3) p[b + 1].z() = 0.051f + 0.01f * unit(random);  // far off screen
    t.push_back({b, b + 1, b + 2});
  }
  const Picture expected = everyPixelOfEveryBox(p, t, view());
  const Picture drawn = rasterize({p, t, {}}, view());
  std::size_t covered = 0;
  for (const std::uint32_t f : drawn.face) covered += f != kNoFace ? 1 : 0;
  EXPECT_GT(covered, 10000u);  // of 20,000 pixels: the comparison is not of two empty pictures
  EXPECT_EQ(drawn.face, expected.face);
  EXPECT_EQ(drawn.depth.data(), expected.depth.data());
}

TEST(Splat, DiscsOfWorldRadiusNearestWins) {
  const std::vector<Eigen::Vector3f> points{{0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 8.0f}, {0.0f, 0.0f, -3.0f}};
  const std::vector<Eigen::Vector3f> colours{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Picture pic = splat(points, colours, 0.1, view());  // 2 px at 5 m, 1.25 px at 8 m
  std::size_t first = 0, second = 0;
  for (const std::uint32_t f : pic.face) {
    first += f == 0 ? 1 : 0;
    second += f == 1 ? 1 : 0;
    ASSERT_NE(f, 2u);  // behind the camera
  }
  EXPECT_EQ(first, 12u);  // pixel centres within 2 px of (99.5, 49.5): offsets (0.5, 0.5), (0.5, 1.5), (1.5, 0.5) x 4
  EXPECT_EQ(second, 0u);  // hidden behind the nearer disc
  EXPECT_NEAR(pic.depth.at(100, 50), 5.0f, 1e-5f);
  EXPECT_EQ(pic.colour.at(100, 50, 0), 1.0f);
}

}  // namespace
}  // namespace artemis::render
