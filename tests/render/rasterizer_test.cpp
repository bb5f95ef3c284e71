// The rasterizer against pictures whose answers are known: a square at a known depth, occlusion,
// perspective-correct colour, faces behind the camera, broken input, thread-count independence.
#include "artemis/render/rasterizer.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

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
