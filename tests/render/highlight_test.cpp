// Highlight colouring: which vertices a query's classes light up, and how a picture shows them.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "artemis/render/highlight.hpp"
#include "artemis/render/rasterizer.hpp"

namespace artemis::render {
namespace {

TEST(Highlight, VertexRanksFollowTheQuerysClassOrder) {
  const std::vector<std::uint8_t> vertex_class = {0, 1, 6, 13, 1, 6, 200};
  const std::vector<std::uint8_t> classes = {6, 1};
  const auto h = vertexHighlight(vertex_class, classes);
  EXPECT_EQ(h, (std::vector<std::uint8_t>{0, 2, 1, 0, 2, 1, 0}));
  EXPECT_TRUE(vertexHighlight(vertex_class, {}).size() == vertex_class.size());
  for (const std::uint8_t x : vertexHighlight(vertex_class, {})) EXPECT_EQ(x, 0);
  EXPECT_NE(highlightColour(0), highlightColour(1));
  EXPECT_EQ(highlightColour(0), highlightColour(kHighlightColours));
}

// A 4 m x 2 m wall 10 m in front of the camera, two faces; vertices at x = -2 are class 1
// ("car"), those at x = +2 are not, so the highlight must end half-way, where the nearest vertex
// changes, not at a face edge.
struct Wall {
  std::vector<Eigen::Vector3f> positions = {{-2, -1, 10}, {2, -1, 10}, {2, 1, 10}, {-2, 1, 10}};
  std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  View view;
  Wall() {
    view.camera = {200, 100, 100.0, 100.0, 99.5, 49.5};
    view.T_W_C = Isometry3d::Identity();
  }
};

TEST(Highlight, PixelsTakeTheirNearestVertexsHighlight) {
  const Wall wall;
  const MeshArrays mesh{wall.positions, wall.triangles, {}};
  const Picture picture = rasterize(mesh, wall.view);
  const std::vector<std::uint8_t> cls = {1, 0, 0, 1};
  const std::vector<std::uint8_t> query = {1};
  const ShadedPicture shaded = shade(mesh, picture, wall.view, vertexHighlight(cls, query));
  // The wall spans u = 99.5 +- 20, v = 49.5 +- 10.
  EXPECT_EQ(shaded.covered_pixels, 40u * 20u);
  EXPECT_GT(shaded.highlighted_pixels, 0u);
  std::size_t left = 0, right = 0;
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 200; ++u) {
      if (shaded.mask.at(u, v) == 0) continue;
      (u < 100 ? left : right) += 1;
    }
  }
  // Highlighted pixels lie on the class-1 side; a quarter of the width may spill across the
  // diagonal, where the nearest vertex is a class-1 corner.
  EXPECT_GT(left, 0.8 * (20 * 20));
  EXPECT_LT(right, 0.3 * (20 * 20));
  const Rgb8 yellow = highlightColour(0);
  EXPECT_NEAR(shaded.image.at(85, 49, 0), 0.75 * yellow[0] + 0.25 * 200 * 1.0, 30);
  EXPECT_EQ(shaded.image.at(5, 5, 0), 255);  // background
  EXPECT_EQ(shaded.mask.at(5, 5), 0);
}

TEST(Highlight, NoQueryNoHighlightAndUntexturedSurfacesAreShaded) {
  Wall wall;
  const MeshArrays mesh{wall.positions, wall.triangles, {}};
  const ShadedPicture facing = shade(mesh, rasterize(mesh, wall.view), wall.view, {});
  EXPECT_EQ(facing.highlighted_pixels, 0u);
  // Tilt the wall 60 degrees: it faces the camera less and is drawn darker.
  Wall tilted;
  for (auto& p : tilted.positions) p.z() += p.x() * 1.732f;
  const MeshArrays tilted_mesh{tilted.positions, tilted.triangles, {}};
  const Picture picture = rasterize(tilted_mesh, tilted.view);
  const ShadedPicture dark = shade(tilted_mesh, picture, tilted.view, {});
  int u = -1;
  for (int x = 0; x < 200 && u < 0; ++x) u = picture.faceAt(x, 49) != kNoFace ? x + 2 : -1;
  ASSERT_GE(u, 0);
  EXPECT_LT(dark.image.at(u, 49, 0) + 20, facing.image.at(99, 49, 0));
}

TEST(Highlight, TexturedPixelsKeepTheirColour) {
  const Wall wall;
  const std::vector<Eigen::Vector3f> colours(4, Eigen::Vector3f(0.2f, 0.4f, 0.6f));
  const MeshArrays mesh{wall.positions, wall.triangles, colours};
  const ShadedPicture shaded = shade(mesh, rasterize(mesh, wall.view), wall.view, {});
  EXPECT_EQ(shaded.image.at(99, 49, 0), 51);
  EXPECT_EQ(shaded.image.at(99, 49, 1), 102);
  EXPECT_EQ(shaded.image.at(99, 49, 2), 153);
}

}  // namespace
}  // namespace artemis::render
