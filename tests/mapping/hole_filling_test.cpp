// Hole filling on small hand-made meshes: which holes close, with what faces, and which gaps
// (an island's outline, a step, a gap wider than the mesher's longest edge) stay open.

#include "artemis/mapping/hole_filling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "mesh_checks.hpp"

namespace artemis::mapping {
namespace {

constexpr double kMaxEdge = 0.6;  // the mesher's default longest edge

// A flat grid of n x n vertices `step` apart at z = 0, its faces wound counter-clockwise seen
// from above (normals +z); face 2 * (row * (n - 1) + col) and the next one make up each quad.
struct Grid {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Face> faces;
  int n = 0;

  Grid(int size, float step) : n(size) {
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c)
        positions.emplace_back(static_cast<float>(c) * step, static_cast<float>(r) * step, 0.0f);
    }
    for (int r = 0; r + 1 < n; ++r) {
      for (int c = 0; c + 1 < n; ++c) {
        faces.push_back({id(r, c), id(r, c + 1), id(r + 1, c + 1)});
        faces.push_back({id(r, c), id(r + 1, c + 1), id(r + 1, c)});
      }
    }
  }
  [[nodiscard]] std::uint32_t id(int r, int c) const { return static_cast<std::uint32_t>(r * n + c); }
  // Removes the two faces of quad (r, c).
  void punch(int r, int c) {
    const auto quad = static_cast<std::size_t>(2 * (r * (n - 1) + c));
    faces.erase(faces.begin() + static_cast<std::ptrdiff_t>(quad),
                faces.begin() + static_cast<std::ptrdiff_t>(quad) + 2);
  }
  [[nodiscard]] std::vector<Face> with(const std::vector<Face>& fills) const {
    std::vector<Face> all = faces;
    all.insert(all.end(), fills.begin(), fills.end());
    return all;
  }
  [[nodiscard]] float normalZ(const Face& f) const {
    const Eigen::Vector3f& a = positions[f[0]];
    return (positions[f[1]] - a).cross(positions[f[2]] - a).normalized().z();
  }
};

// Quads are removed from the back of the face list first, so that earlier indices stay valid.
TEST(HoleFilling, ClosesAMissingQuadLikeTheFacesAround) {
  Grid grid(6, 0.2f);
  const std::size_t outline = artemis::test::boundaryEdges(grid.faces).size();
  grid.punch(2, 2);
  ASSERT_EQ(artemis::test::boundaryEdges(grid.faces).size(), outline + 4);
  HoleFillStats stats;
  const std::vector<Face> fills = holeFillingFaces(grid.faces, grid.positions, kMaxEdge, {}, &stats);
  ASSERT_EQ(fills.size(), 2u);
  EXPECT_EQ(stats.filled, 1u);
  for (const Face& f : fills) EXPECT_GT(grid.normalZ(f), 0.99f);  // wound like the grid
  const std::vector<Face> all = grid.with(fills);
  EXPECT_EQ(artemis::test::boundaryEdges(all).size(), outline);  // only the grid's own outline is left
  const artemis::test::MeshChecks checks = artemis::test::checkMesh(grid.positions, all);
  EXPECT_EQ(checks.non_manifold_edges, 0u);
  EXPECT_EQ(checks.duplicate_faces, 0u);
  EXPECT_EQ(checks.zero_area_faces, 0u);
}

TEST(HoleFilling, ClosesTwoHolesThatTouchAtACorner) {
  Grid grid(7, 0.2f);
  const std::size_t outline = artemis::test::boundaryEdges(grid.faces).size();
  grid.punch(3, 3);  // shares vertex (3, 3) with quad (2, 2)
  grid.punch(2, 2);
  HoleFillStats stats;
  const std::vector<Face> fills = holeFillingFaces(grid.faces, grid.positions, kMaxEdge, {}, &stats);
  EXPECT_EQ(stats.filled, 2u);
  EXPECT_EQ(fills.size(), 4u);
  EXPECT_EQ(artemis::test::boundaryEdges(grid.with(fills)).size(), outline);
  EXPECT_EQ(artemis::test::checkMesh(grid.positions, grid.with(fills)).non_manifold_edges, 0u);
}

TEST(HoleFilling, LeavesAnIslandsOutlineAlone) {
  // One triangle on its own: its three edges are a loop, but one that runs with its face.
  const std::vector<Eigen::Vector3f> positions{{0, 0, 0}, {0.2f, 0, 0}, {0, 0.2f, 0}};
  HoleFillStats stats;
  EXPECT_TRUE(holeFillingFaces({{0, 1, 2}}, positions, kMaxEdge, {}, &stats).empty());
  EXPECT_EQ(stats.loops, 1u);
  EXPECT_EQ(stats.islands, 1u);
}

TEST(HoleFilling, LeavesAStepOpen) {
  // The vertices of columns 3 and beyond stand 0.3 m higher; the quad across the step in row 2 is
  // missing: its corners lie ~8 cm off the plane of the faces around (two flat, two up the step).
  Grid grid(6, 0.2f);
  for (int r = 0; r < grid.n; ++r) {
    for (int c = 3; c < grid.n; ++c) grid.positions[grid.id(r, c)].z() = 0.3f;
  }
  grid.punch(2, 2);
  HoleFillStats stats;
  EXPECT_TRUE(holeFillingFaces(grid.faces, grid.positions, kMaxEdge, {}, &stats).empty());
  EXPECT_EQ(stats.bumpy, 1u);
  // A low step (2 cm, noise on a road) is closed.
  for (int r = 0; r < grid.n; ++r) {
    for (int c = 3; c < grid.n; ++c) grid.positions[grid.id(r, c)].z() = 0.02f;
  }
  EXPECT_EQ(holeFillingFaces(grid.faces, grid.positions, kMaxEdge, {}).size(), 2u);
}

TEST(HoleFilling, LeavesAGapInFoliageOpen) {
  // The hole's corners lie flat, but every other vertex is 0.3 m up or down in turn: the faces
  // around the hole lean every way, as in a hedge.
  Grid grid(6, 0.2f);
  for (int r = 0; r < grid.n; ++r) {
    for (int c = 0; c < grid.n; ++c) {
      const bool corner = (r == 2 || r == 3) && (c == 2 || c == 3);
      if (!corner) grid.positions[grid.id(r, c)].z() = (r + c) % 2 == 0 ? 0.3f : -0.3f;
    }
  }
  grid.punch(2, 2);
  HoleFillStats stats;
  EXPECT_TRUE(holeFillingFaces(grid.faces, grid.positions, kMaxEdge, {}, &stats).empty());
  EXPECT_EQ(stats.rough, 1u);
  HoleFillParams any_way;
  any_way.min_normal_agreement = 0.0;
  EXPECT_EQ(holeFillingFaces(grid.faces, grid.positions, kMaxEdge, any_way).size(), 2u);
}

TEST(HoleFilling, LeavesGapsWiderThanTheLongestEdgeOpen) {
  Grid grid(6, 0.7f);  // a quad 0.7 m a side: wider than the longest edge (0.6)
  grid.punch(2, 2);
  HoleFillStats stats;
  EXPECT_TRUE(holeFillingFaces(grid.faces, grid.positions, kMaxEdge, {}, &stats).empty());
  EXPECT_EQ(stats.long_edges, 1u);
  // Nor does a loop of more edges than allowed close: a 2 x 2 block of quads has 8 edges.
  Grid block(7, 0.1f);
  for (const auto& [r, c] : std::vector<std::pair<int, int>>{{3, 3}, {3, 2}, {2, 3}, {2, 2}}) block.punch(r, c);
  HoleFillParams six;
  six.max_loop_edges = 6;
  EXPECT_TRUE(holeFillingFaces(block.faces, block.positions, kMaxEdge, six).empty());
  EXPECT_EQ(holeFillingFaces(block.faces, block.positions, kMaxEdge, {}).size(), 6u);  // 8 corners: 6 faces
}

TEST(HoleFilling, OffDoesNothing) {
  Grid grid(6, 0.2f);
  grid.punch(2, 2);
  HoleFillParams off;
  off.enabled = false;
  EXPECT_TRUE(holeFillingFaces(grid.faces, grid.positions, kMaxEdge, off).empty());
}

}  // namespace
}  // namespace artemis::mapping
