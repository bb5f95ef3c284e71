// The evaluator's parallel voxel downsampling against the core's sequential VoxelAccumulator
// (an independent implementation of the same rule), and its independence of the thread count.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <limits>
#include <random>

#include "artemis/core/voxel_downsample.hpp"
#include "voxel_centroids.hpp"

namespace artemis::eval::detail {
namespace {

bool lexicographic(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

std::vector<Eigen::Vector3f> randomCloud(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xy(-30.0F, 30.0F);
  std::uniform_real_distribution<float> z(-2.0F, 2.0F);
  std::vector<Eigen::Vector3f> points(n);
  for (auto& p : points) p = {xy(rng), xy(rng), z(rng)};
  return points;
}

TEST(VoxelCentroids, MatchesTheCoreVoxelAccumulator) {
  auto points = randomCloud(600'000, 1);  // several buckets and scatter chunks
  points.emplace_back(std::numeric_limits<float>::quiet_NaN(), 0.0F, 0.0F);
  points.emplace_back(1e9F, 0.0F, 0.0F);  // beyond the key range: dropped by both
  for (const double voxel_m : {0.05, 0.3}) {
    auto ours = voxelCentroids(points, voxel_m);
    PointCloud cloud;
    cloud.points = points;
    auto theirs = voxelDownsample(cloud, voxel_m).cloud.points;
    ASSERT_EQ(ours.size(), theirs.size()) << voxel_m;
    std::sort(ours.begin(), ours.end(), lexicographic);
    std::sort(theirs.begin(), theirs.end(), lexicographic);
    // Both sum in double in input order: the centroids agree to the bit.
    EXPECT_TRUE(ours == theirs) << voxel_m;
  }
  // 0.05 m: 115 million voxels for 600k points, nearly all alone. 0.3 m: 200 x 200 x 14 voxels,
  // 1.07 points each on average, so 1 - exp(-1.07) = 66 % occupied.
  EXPECT_GT(voxelCentroids(points, 0.05).size(), 598'000U);
  EXPECT_NEAR(static_cast<double>(voxelCentroids(points, 0.3).size()), 0.657 * 560'000.0, 10'000.0);
}

TEST(VoxelCentroids, SameResultOnOneThread) {
  const auto points = randomCloud(300'000, 2);
  const auto parallel = voxelCentroids(points, 0.1);
  std::vector<Eigen::Vector3f> serial;
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { serial = voxelCentroids(points, 0.1); });
  EXPECT_TRUE(parallel == serial);  // same order, same values
}

TEST(VoxelCentroids, DegenerateInput) {
  EXPECT_TRUE(voxelCentroids({}, 0.1).empty());
  const std::vector<Eigen::Vector3f> same(1000, Eigen::Vector3f(1.02F, -3.0F, 0.5F));
  const auto one = voxelCentroids(same, 0.1);
  ASSERT_EQ(one.size(), 1U);
  EXPECT_EQ(one[0], same[0]);
  EXPECT_THROW((void)voxelCentroids(same, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace artemis::eval::detail
