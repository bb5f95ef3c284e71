// The simulated LiDAR against the ground-truth surface, checked without ray casting: every point
// is found on the mesh by an independent nearest-triangle search.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sim_fixture.hpp"
#include "triangle_grid.hpp"

namespace artemis::sim {
namespace {

using test::defaultSim;
using test::noiseFreeSim;
using test::TriangleGrid;

TEST(SimLidar, ScanLooksLikeKittis) {
  const Simulator& sim = defaultSim();
  const LidarScan scan = sim.scan(0);
  ASSERT_EQ(scan.labels.size(), scan.points_L.size());
  EXPECT_GT(scan.points_L.size(), 100000u);
  EXPECT_LT(scan.points_L.size(), 140000u);
  double min_elev = 90;
  double max_elev = -90;
  double max_range = 0;
  for (std::size_t i = 0; i < scan.points_L.size(); ++i) {
    const Eigen::Vector4f& p = scan.points_L[i];
    ASSERT_GE(p.w(), 0.0f);
    ASSERT_LE(p.w(), 1.0f);
    const double r = p.head<3>().cast<double>().norm();
    max_range = std::max(max_range, r);
    const double e = std::asin(p.z() / r) * 180.0 / std::numbers::pi;
    min_elev = std::min(min_elev, e);
    max_elev = std::max(max_elev, e);
    ASSERT_NE(scan.labels[i] & 0xFFFFu, 0u) << "point " << i << " has no class";
  }
  EXPECT_NEAR(min_elev, -24.9, 0.1);
  EXPECT_LE(max_elev, 2.05);
  EXPECT_GT(max_elev, 0.0);  // the upper beams reach the facades
  EXPECT_LE(max_range, sim.params().lidar.max_range_m + 0.2);
}

// 99 % of the points lie within 3 sigma of the surface; the noise is there (not all on it).
TEST(SimLidar, PointsLieOnTheSurfaceWithinTheRangeNoise) {
  const Simulator& sim = defaultSim();
  const double sigma = sim.params().lidar.range_noise_m;
  const TriangleGrid grid(sim.scene().mesh.vertices, sim.scene().mesh.triangles, 1.0);
  std::size_t n = 0;
  std::size_t within = 0;
  std::size_t off_surface = 0;
  for (int frame : {0, 5}) {
    const LidarScan scan = sim.scan(frame);
    const Isometry3d T_S_L = sim.T_S_L(frame);
    for (std::size_t i = 0; i < scan.points_L.size(); i += 13) {
      const Eigen::Vector3d p_S = T_S_L * scan.points_L[i].head<3>().cast<double>();
      const auto nearest = grid.nearest(p_S, 10 * sigma);
      ++n;
      within += nearest.distance_m <= 3 * sigma ? 1 : 0;
      off_surface += nearest.distance_m > 0.5 * sigma ? 1 : 0;
    }
  }
  const double share = static_cast<double>(within) / static_cast<double>(n);
  std::printf("points within 3 sigma of the surface: %.4f of %zu; beyond sigma/2: %.3f\n", share, n,
              static_cast<double>(off_surface) / static_cast<double>(n));
  EXPECT_GE(share, 0.99);
  EXPECT_GT(static_cast<double>(off_surface) / static_cast<double>(n), 0.1);
}

// Without noise every point is on a triangle of its label's class and instance.
TEST(SimLidar, LabelIsTheClassOfTheTriangleHit) {
  const Simulator& sim = noiseFreeSim();
  const SceneMesh& mesh = sim.scene().mesh;
  const TriangleGrid grid(mesh.vertices, mesh.triangles, 1.0);
  std::size_t n = 0;
  std::size_t matched = 0;
  for (int frame : {0, 3}) {
    const LidarScan scan = sim.scan(frame);
    const Isometry3d T_S_L = sim.T_S_L(frame);
    for (std::size_t i = 0; i < scan.points_L.size(); i += 7) {
      const Eigen::Vector3d p_S = T_S_L * scan.points_L[i].head<3>().cast<double>();
      const std::uint32_t label = scan.labels[i];
      // Surfaces face outward: no ray hits the back of a face.
      const Eigen::Vector3d ray = p_S - T_S_L.translation();
      ASSERT_LT(mesh.faceNormal(scan.faces[i]).dot(ray), 0.0) << "back face hit at point " << i;
      bool ok = false;
      for (std::uint32_t f : grid.within(p_S, 2e-3)) {
        ok = ok || (mesh.face_class[f] == (label & 0xFFFFu) && mesh.face_instance[f] == (label >> 16));
      }
      ++n;
      matched += ok ? 1 : 0;
    }
  }
  std::printf("noise-free points on a triangle of their label: %zu of %zu\n", matched, n);
  EXPECT_EQ(matched, n);
}

TEST(SimLidar, SameFrameSameScan) {
  const Simulator& sim = defaultSim();
  const LidarScan a = sim.scan(2);
  const LidarScan b = sim.scan(2);
  EXPECT_EQ(a.labels, b.labels);
  ASSERT_EQ(a.points_L.size(), b.points_L.size());
  EXPECT_TRUE(std::equal(a.points_L.begin(), a.points_L.end(), b.points_L.begin()));
  const LidarScan c = sim.scan(3);
  EXPECT_NE(a.labels.size() == c.labels.size() && a.labels == c.labels, true);
}

TEST(SimTrajectory, DrivesDownTheStreetAt5To15MetresASecond) {
  const Simulator& sim = defaultSim();
  SimParams p = sim.params();
  for (int k = 0; k < 300; ++k) {
    const double v = sim.speed_mps(k);
    ASSERT_GE(v, 5.0);
    ASSERT_LE(v, 15.0);
  }
  EXPECT_TRUE(sim.T_W_L(0).isApprox(Isometry3d::Identity(), 1e-12));
  for (int k = 1; k < sim.frames(); ++k) {
    const Isometry3d step = sim.T_W_L(k - 1).inverse() * sim.T_W_L(k);
    EXPECT_GT(step.translation().x(), 0.5);  // forward, 0.5..1.5 m a frame at 10 Hz
    EXPECT_LT(step.translation().x(), 1.5);
    EXPECT_LT(std::abs(step.translation().y()), 0.05);
    EXPECT_LT(rotationAngleDeg(step), 1.0);  // gentle yaw changes
    const Isometry3d T_S_L = sim.T_S_L(k);
    EXPECT_NEAR(T_S_L.translation().z(), p.lidar.mount_height_m, 1e-12);
    EXPECT_LT(T_S_L.translation().y(), 0.0);  // right-hand lane
    EXPECT_GT(T_S_L.translation().y(), -p.scene.lane_width_m);
  }
}

}  // namespace
}  // namespace artemis::sim
