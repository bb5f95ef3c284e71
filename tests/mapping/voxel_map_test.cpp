// The voxel map against brute force: one point per sub-cell, the active set, bad points.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>
#include <limits>
#include <set>
#include <tuple>

#include "artemis/mapping/voxel_map.hpp"

namespace artemis::mapping {
namespace {

TEST(VoxelMap, KeepsOnePointPerSubCellAndReportsActiveVoxels) {
  VoxelMap map({.voxel_size_m = 0.4, .subdivisions = 8});
  SemanticMesh mesh;
  std::vector<Eigen::Vector3f> points;
  // A 1 m x 1 m patch sampled every 1 cm: 0.05 m sub-cells keep 20 x 20 points.
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 100; ++j)
      points.emplace_back(0.005f + 0.01f * static_cast<float>(i), 0.005f + 0.01f * static_cast<float>(j), 0.02f);
  }
  const auto active = map.insert(points, {0, 0, 2}, mesh);
  EXPECT_EQ(mesh.vertexCount(), 400u);
  // Voxels touched: x and y in [0, 1) span keys 0..2 each, z key 0.
  std::set<std::tuple<int, int, int>> expected;
  for (const auto& p : points) {
    expected.emplace(static_cast<int>(std::floor(p.x() / 0.4f)), static_cast<int>(std::floor(p.y() / 0.4f)), 0);
  }
  EXPECT_EQ(active.size(), expected.size());
  std::set<std::tuple<int, int, int>> got;
  for (const auto& k : active) got.emplace(k.x, k.y, k.z);
  EXPECT_EQ(got, expected);

  // The same scan again adds nothing and activates nothing.
  EXPECT_TRUE(map.insert(points, {0, 0, 2}, mesh).empty());
  EXPECT_EQ(mesh.vertexCount(), 400u);
  // A point in an empty sub-cell activates exactly its voxel.
  const auto one = map.insert({{0.1f, 0.1f, 0.3f}}, {0, 0, 2}, mesh);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], (VoxelKey{0, 0, 0}));
  EXPECT_EQ(mesh.vertexCount(), 401u);
  // Vertices remember their voxel and point towards the sensor.
  EXPECT_EQ(mesh.voxels().back(), (VoxelKey{0, 0, 0}));
  EXPECT_GT(mesh.viewDirections().back().z(), 0.9f);
}

// Enough voxels to grow the hash table several times, against a brute-force set of keys.
TEST(VoxelMap, ManyVoxelsMatchBruteForce) {
  VoxelMap map({.voxel_size_m = 0.4, .subdivisions = 4});
  SemanticMesh mesh;
  std::vector<Eigen::Vector3f> points;
  std::set<std::tuple<int, int, int>> expected;
  for (int i = 0; i < 120000; ++i) {
    const Eigen::Vector3f p(std::fmod(static_cast<float>(i) * 0.731f, 97.0f) - 48.0f,
                            std::fmod(static_cast<float>(i) * 0.377f, 89.0f) - 44.0f,
                            std::fmod(static_cast<float>(i) * 0.193f, 7.0f) - 3.0f);
    points.push_back(p);
    expected.emplace(static_cast<int>(std::floor(p.x() / 0.4f)), static_cast<int>(std::floor(p.y() / 0.4f)),
                     static_cast<int>(std::floor(p.z() / 0.4f)));
  }
  const auto active = map.insert(points, {0, 0, 0}, mesh);
  EXPECT_GT(expected.size(), 40000u);
  EXPECT_EQ(map.size(), expected.size());
  EXPECT_EQ(active.size(), expected.size());
  for (const auto& [x, y, z] : expected) ASSERT_NE(map.find({x, y, z}), nullptr);
  EXPECT_EQ(map.find({1000, 1000, 1000}), nullptr);
  // Huge coordinates (a broken pose) are refused and counted, not turned into wrapped keys.
  map.insert({{3e9f, 0.0f, 0.0f}}, {0, 0, 0}, mesh);
  EXPECT_EQ(map.rejectedPoints(), 1u);
}

TEST(VoxelMap, NegativeCoordinatesAndBadPoints) {
  VoxelMap map({.voxel_size_m = 0.5, .subdivisions = 4});
  SemanticMesh mesh;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const auto active =
      map.insert({{-0.01f, -0.26f, -1.0f}, {nan, 0, 0}, {0, inf, 0}, {-0.49f, -0.49f, -0.99f}}, {0, 0, 0}, mesh);
  ASSERT_EQ(active.size(), 1u);
  EXPECT_EQ(active[0], (VoxelKey{-1, -1, -2}));
  EXPECT_EQ(mesh.vertexCount(), 2u);
  EXPECT_THROW(VoxelMap({.voxel_size_m = 0.0, .subdivisions = 8}), std::invalid_argument);
  EXPECT_THROW(VoxelMap({.voxel_size_m = 0.4, .subdivisions = 9}), std::invalid_argument);
}

TEST(VoxelMap, DroppedPointsAreLeftOutButNotRefused) {
  VoxelMap map({.voxel_size_m = 0.5, .subdivisions = 4});
  SemanticMesh mesh;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> points{{0.1f, 0.1f, 0.1f}, {1.1f, 0.1f, 0.1f}, {nan, 0, 0}, {2.1f, 0.1f, 0.1f}};
  const std::vector<std::uint8_t> drop{0, 1, 0, 0};
  const auto active = map.insert(points, {0, 0, 2}, mesh, &drop);
  EXPECT_EQ(active.size(), 2u);
  EXPECT_EQ(mesh.vertexCount(), 2u);
  EXPECT_EQ(map.rejectedPoints(), 1u);  // the NaN only
  EXPECT_NE(map.insertedVertex(0), VoxelMap::kNoVertex);
  EXPECT_EQ(map.insertedVertex(1), VoxelMap::kNoVertex);
  EXPECT_EQ(map.insertedVertex(2), VoxelMap::kNoVertex);
  EXPECT_NE(map.insertedVertex(3), VoxelMap::kNoVertex);
  const std::vector<std::uint8_t> short_mask{0, 1};
  EXPECT_THROW(map.insert(points, {0, 0, 2}, mesh, &short_mask), std::invalid_argument);
}

// A plane fitted to a voxel's points (FreeSpaceCarver::planeOf) is kept while the voxel holds as
// many points as it was fitted to; after points went, the same count later is other points.
TEST(VoxelMap, RemovingPointsForgetsThePlaneFittedToThem) {
  VoxelMap map({.voxel_size_m = 1.0, .subdivisions = 4});
  SemanticMesh mesh;
  const std::vector<Eigen::Vector3f> points{{0.1f, 0.1f, 0.1f}, {0.6f, 0.1f, 0.1f}, {0.1f, 0.6f, 0.1f}};
  map.insert(points, {0, 0, 2}, mesh);
  const std::uint32_t index = map.indexOf(map.keyOf(points[0]));
  ASSERT_NE(index, VoxelMap::kNoVertex);
  Voxel& v = map.voxelAt(index);
  ASSERT_EQ(v.points.size(), 3u);
  v.plane_points = 3;  // as a fit to these three points leaves it
  std::vector<std::uint32_t> removed;
  map.removePoints(index, {0, 0, 0}, removed);  // nothing goes: the fit stands
  EXPECT_EQ(v.plane_points, 3u);
  map.removePoints(index, {0, 1, 0}, removed);
  EXPECT_EQ(removed.size(), 1u);
  EXPECT_EQ(v.plane_points, 0u);
  map.insert({{0.6f, 0.6f, 0.1f}}, {0, 0, 2}, mesh);  // three points again, not those of the fit
  EXPECT_EQ(v.points.size(), 3u);
  EXPECT_NE(v.plane_points, v.points.size());
}

}  // namespace
}  // namespace artemis::mapping
