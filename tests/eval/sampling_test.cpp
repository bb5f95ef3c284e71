// sampleSurface: exact counts, uniform density (checked against areas), determinism for a seed
// and for any thread count, and degenerate triangles.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <limits>

#include "artemis/eval/geometry.hpp"
#include "scenes.hpp"

namespace artemis::eval {
namespace {

using test::square;

TEST(SurfaceSampling, CountFollowsAreaAndTheMinimum) {
  EXPECT_EQ(sampleSurface(square(), 400.0, 0, 1).size(), 40'000U);         // 100 m^2 at 400 / m^2
  EXPECT_EQ(sampleSurface(square(), 400.0, 100'000, 1).size(), 100'000U);  // the floor wins
  EXPECT_EQ(sampleSurface(square(), 400.0, 2'000'000, 1).size(), 2'000'000U);
  EXPECT_EQ(sampleSurface(square(), 12.5, 0, 1).size(), 1'250U);
}

TEST(SurfaceSampling, SamplesAreUniformOverTheSurface) {
  const auto samples = sampleSurface(square(), 400.0, 0, 7);
  // Every sample on the square; 400 expected in each 1 x 1 m cell (sd 20; the 4x4 mesh cells
  // each get their exact share, so cells spread less than a Poisson count would).
  std::vector<int> cells(100, 0);
  for (const auto& p : samples) {
    ASSERT_EQ(p.z(), 0.0F);
    ASSERT_GE(p.x(), 0.0F);
    ASSERT_LE(p.x(), 10.0F);
    ASSERT_GE(p.y(), 0.0F);
    ASSERT_LE(p.y(), 10.0F);
    const int i = std::min(9, static_cast<int>(p.x()));
    const int j = std::min(9, static_cast<int>(p.y()));
    ++cells[static_cast<std::size_t>(10 * j + i)];
  }
  for (std::size_t c = 0; c < cells.size(); ++c) {
    EXPECT_GT(cells[c], 320) << "cell " << c;
    EXPECT_LT(cells[c], 480) << "cell " << c;
  }
}

TEST(SurfaceSampling, UniformInsideOneTriangle) {
  // The right triangle (0,0), (1,0), (0,1): mean at the centroid (1/3, 1/3), and the corner
  // triangle x + y < 0.5 holds a quarter of the area. Barycentric weights drawn naively
  // (uniform r1, r2 normalised) fail both.
  MeshArrays tri;
  tri.vertices = {{0.0F, 0.0F, 0.0F}, {1.0F, 0.0F, 0.0F}, {0.0F, 1.0F, 0.0F}};
  tri.triangles = {{0, 1, 2}};
  const auto samples = sampleSurface(tri, 200'000.0, 0, 3);
  ASSERT_EQ(samples.size(), 100'000U);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t corner = 0;
  for (const auto& p : samples) {
    ASSERT_GE(p.x(), 0.0F);
    ASSERT_GE(p.y(), 0.0F);
    ASSERT_LE(p.x() + p.y(), 1.0F + 1e-6F);
    mean += p.cast<double>();
    if (p.x() + p.y() < 0.5F) ++corner;
  }
  mean /= static_cast<double>(samples.size());
  EXPECT_NEAR(mean.x(), 1.0 / 3.0, 0.005);
  EXPECT_NEAR(mean.y(), 1.0 / 3.0, 0.005);
  EXPECT_NEAR(static_cast<double>(corner) / static_cast<double>(samples.size()), 0.25, 0.005);
}

TEST(SurfaceSampling, TrianglesGetTheirShareOfTheArea) {
  // Two triangles with areas 1 and 3 m^2 share 4000 samples 1000 : 3000 (each within one).
  MeshArrays mesh;
  mesh.vertices = {{0.0F, 0.0F, 0.0F}, {2.0F, 0.0F, 0.0F}, {0.0F, 1.0F, 0.0F},
                   {0.0F, 0.0F, 5.0F}, {3.0F, 0.0F, 5.0F}, {0.0F, 2.0F, 5.0F}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  const auto samples = sampleSurface(mesh, 1000.0, 0, 11);
  ASSERT_EQ(samples.size(), 4000U);
  const auto low = std::count_if(samples.begin(), samples.end(), [](const auto& p) { return p.z() == 0.0F; });
  EXPECT_NEAR(static_cast<double>(low), 1000.0, 1.0);
}

TEST(SurfaceSampling, DeterministicForASeedAndAnyThreadCount) {
  MeshArrays mesh = square();
  test::append(mesh, test::rectangle({0.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F}, {0.0F, 0.0F, 3.0F}, 7));
  const auto a = sampleSurface(mesh, 400.0, 1'000'000, 5);
  const auto b = sampleSurface(mesh, 400.0, 1'000'000, 5);
  std::vector<Eigen::Vector3f> serial;
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { serial = sampleSurface(mesh, 400.0, 1'000'000, 5); });
  ASSERT_EQ(a.size(), 1'000'000U);
  EXPECT_TRUE(a == b);
  EXPECT_TRUE(a == serial);
  const auto other_seed = sampleSurface(mesh, 400.0, 1'000'000, 6);
  ASSERT_EQ(other_seed.size(), a.size());
  std::size_t same = 0;
  for (std::size_t i = 0; i < a.size(); ++i) same += a[i] == other_seed[i] ? 1 : 0;
  EXPECT_LT(same, 10U);
}

TEST(SurfaceSampling, DegenerateTrianglesGetNoSamples) {
  const auto reference = sampleSurface(square(), 400.0, 0, 9);
  MeshArrays mesh = square();
  // Zero area (collinear, repeated corner) and non-finite corners, far from the square.
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  mesh.vertices.insert(
      mesh.vertices.end(),
      {{100.0F, 0.0F, 0.0F}, {101.0F, 0.0F, 0.0F}, {102.0F, 0.0F, 0.0F}, {nan, 50.0F, 0.0F}, {inf, 60.0F, 0.0F}});
  mesh.triangles.push_back({base, base + 1, base + 2});
  mesh.triangles.push_back({base, base, base + 1});
  mesh.triangles.push_back({base, base + 1, base + 3});
  mesh.triangles.push_back({base, base + 4, base + 1});
  const auto samples = sampleSurface(mesh, 400.0, 0, 9);
  // The same samples as the square alone: the extra triangles add no area and take none.
  EXPECT_TRUE(samples == reference);

  MeshArrays only_degenerate;
  only_degenerate.vertices = {{0.0F, 0.0F, 0.0F}, {1.0F, 1.0F, 1.0F}, {2.0F, 2.0F, 2.0F}};
  only_degenerate.triangles = {{0, 1, 2}};
  EXPECT_TRUE(sampleSurface(only_degenerate, 400.0, 2'000'000, 1).empty());
  EXPECT_TRUE(sampleSurface(MeshArrays{}, 400.0, 2'000'000, 1).empty());

  MeshArrays bad_index = square();
  bad_index.triangles.push_back({0, 1, 1000});
  EXPECT_THROW((void)sampleSurface(bad_index, 400.0, 0, 1), std::invalid_argument);
  EXPECT_THROW((void)sampleSurface(square(), 0.0, 0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace artemis::eval
