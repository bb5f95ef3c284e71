#include "artemis/registration/local_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "scenes.hpp"

namespace artemis::registration {
namespace {

std::vector<Eigen::Vector3f> groundPatch(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3f> p;
  test::samplePlane(p, {-5, -5, 0}, {10, 0, 0}, {0, 10, 0}, 20000, rng);
  return p;
}

TEST(LocalMap, PlanePointsGetThePlaneNormalAndOnePointPerSubCell) {
  LocalMap map(LocalMapParams{});
  const auto added = map.insert(groundPatch(1), Eigen::Vector3f::Zero());
  // 10 m x 10 m at 0.25 m sub-cells: at most 1600 points, and random sampling fills nearly all.
  EXPECT_LE(added, 1600u);
  EXPECT_GE(added, 1500u);
  EXPECT_EQ(map.insert(groundPatch(1), Eigen::Vector3f::Zero()), 0u);  // every sub-cell is taken
  std::vector<Eigen::Vector3f> points, normals;
  map.points(points, normals);
  ASSERT_EQ(points.size(), added);
  std::size_t valid = 0;
  for (const auto& n : normals) {
    if (n.isZero()) continue;
    ++valid;
    EXPECT_NEAR(std::abs(n.z()), 1.0f, 1e-4f);
  }
  EXPECT_GE(valid, added * 95 / 100);  // all but the patch's corners
}

TEST(LocalMap, NearestIsTheClosestSurfelWithinTheDistance) {
  LocalMap map(LocalMapParams{});
  map.insert(groundPatch(2), Eigen::Vector3f::Zero());
  const auto hit = map.nearest({0.3f, -0.2f, 0.1f}, 0.5f);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->point.z(), 0.0f, 1e-6f);
  EXPECT_LE(std::sqrt(hit->distance_sq), 0.1f + 0.25f * std::sqrt(2.0f));
  EXPECT_NEAR(std::abs(hit->normal.z()), 1.0f, 1e-4f);
  // Brute force agrees on the nearest surfel.
  std::vector<Eigen::Vector3f> points, normals;
  map.points(points, normals);
  float best = std::numeric_limits<float>::max();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!normals[i].isZero()) best = std::min(best, (points[i] - Eigen::Vector3f(0.3f, -0.2f, 0.1f)).squaredNorm());
  }
  EXPECT_FLOAT_EQ(hit->distance_sq, best);
  EXPECT_FALSE(map.nearest({0.0f, 0.0f, 2.0f}, 0.5f));  // nothing within 0.5 m
  EXPECT_FALSE(map.nearest({NAN, 0.0f, 0.0f}, 0.5f));
}

TEST(LocalMap, RefusesNonFinitePointsAndCountsThem) {
  LocalMap map(LocalMapParams{});
  std::vector<Eigen::Vector3f> bad{{NAN, 0, 0}, {0, INFINITY, 0}, {2e6f, 0, 0}, {1, 1, 1}};
  EXPECT_EQ(map.insert(bad, Eigen::Vector3f::Zero()), 1u);
  EXPECT_EQ(map.rejectedPoints(), 3u);
}

TEST(LocalMap, DropsVoxelsFarFromTheSensor) {
  LocalMapParams params;
  params.max_distance_m = 50.0;
  LocalMap map(params);
  map.insert(groundPatch(3), Eigen::Vector3f::Zero());
  EXPECT_GT(map.pointCount(), 0u);
  map.insert({}, Eigen::Vector3f(30, 0, 0));  // still within 50 m of the patch
  EXPECT_GT(map.pointCount(), 0u);
  map.insert({}, Eigen::Vector3f(80, 0, 0));
  EXPECT_EQ(map.pointCount(), 0u);
  EXPECT_EQ(map.voxelCount(), 0u);
  EXPECT_FALSE(map.nearest({0, 0, 0}, 1.0f));
}

TEST(LocalMap, RejectsBadParameters) {
  LocalMapParams params;
  params.subdivisions = 9;
  EXPECT_THROW(LocalMap{params}, std::invalid_argument);
  params = {};
  params.voxel_size_m = 0.0;
  EXPECT_THROW(LocalMap{params}, std::invalid_argument);
}

}  // namespace
}  // namespace artemis::registration
