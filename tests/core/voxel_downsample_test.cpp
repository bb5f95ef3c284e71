#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "artemis/core/voxel_downsample.hpp"

namespace artemis {
namespace {

TEST(VoxelDownsample, MatchesBruteForceCentroids) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  PointCloud cloud;
  for (int i = 0; i < 5000; ++i) {
    cloud.points.emplace_back(u(rng), u(rng), u(rng) * 0.2f);
    cloud.intensity.push_back(static_cast<float>(i % 7));
  }
  const double voxel = 0.5;
  const auto result = voxelDownsample(cloud, voxel);
  // Brute force: group by floor(p / voxel).
  std::map<std::tuple<int, int, int>, std::pair<Eigen::Vector3d, int>> groups;  // sum, count
  for (const auto& p : cloud.points) {
    auto key = std::make_tuple(static_cast<int>(std::floor(p.x() / voxel)), static_cast<int>(std::floor(p.y() / voxel)),
                               static_cast<int>(std::floor(p.z() / voxel)));
    auto [it, inserted] = groups.try_emplace(key, Eigen::Vector3d::Zero(), 0);
    auto& g = it->second;
    g.first += p.cast<double>();
    g.second += 1;
  }
  ASSERT_EQ(result.cloud.size(), groups.size());
  ASSERT_EQ(result.cloud.intensity.size(), groups.size());
  for (const auto& c : result.cloud.points) {
    auto key = std::make_tuple(static_cast<int>(std::floor(c.x() / voxel)), static_cast<int>(std::floor(c.y() / voxel)),
                               static_cast<int>(std::floor(c.z() / voxel)));
    const auto it = groups.find(key);
    ASSERT_NE(it, groups.end());
    EXPECT_LT((c.cast<double>() - it->second.first / it->second.second).norm(), 1e-5);
  }
}

TEST(VoxelDownsample, DegenerateInput) {
  PointCloud one_voxel;
  for (int i = 0; i < 100; ++i) one_voxel.points.emplace_back(0.01f * static_cast<float>(i % 3), 0.0f, 0.0f);
  EXPECT_EQ(voxelDownsample(one_voxel, 1.0).cloud.size(), 1u);
  EXPECT_EQ(voxelDownsample(PointCloud{}, 1.0).cloud.size(), 0u);
  PointCloud far;
  far.points = {{1e9f, 0, 0}, {std::nanf(""), 0, 0}, {1, 1, 1}};
  const auto r = voxelDownsample(far, 0.05);
  EXPECT_EQ(r.cloud.size(), 1u);
  EXPECT_EQ(r.out_of_bounds, 2u);
  EXPECT_THROW(voxelDownsample(far, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace artemis
