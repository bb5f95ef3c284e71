// The simulated Livox Avia-like LiDAR (LidarParams::rosette_points_per_s): its points lie in its
// 70.4-degree field looking forward, each at its own time within the frame and exactly on the
// surface as seen from the pose at that time (not from the frame's pose: the motion shows), and
// its non-repetitive rosette covers more of the field the longer it integrates.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "sim_fixture.hpp"
#include "triangle_grid.hpp"

namespace artemis::sim {
namespace {

const Simulator& aviaSim() {
  static const Simulator s([] {
    SimParams p = test::testParams(12, 0.0);
    p.lidar.rosette_points_per_s = 240000.0;
    return p;
  }());
  return s;
}

double offAxisDeg(const Eigen::Vector3f& p) {
  return std::acos(std::clamp(static_cast<double>(p.x()) / p.cast<double>().norm(), -1.0, 1.0)) * 180.0 /
         std::numbers::pi;
}

TEST(SimRosette, PointsLieInTheFieldAtTheirOwnTimes) {
  const Simulator& sim = aviaSim();
  const LidarScan scan = sim.scan(4);
  ASSERT_EQ(scan.time_s.size(), scan.points_L.size());
  EXPECT_GT(scan.points_L.size(), 12000U);  // of 24,000 beams: the sky and the dropout take the rest
  EXPECT_LT(scan.points_L.size(), 24000U);
  double widest = 0.0;
  for (std::size_t i = 0; i < scan.points_L.size(); ++i) {
    ASSERT_GE(scan.time_s[i], 0.0f);
    ASSERT_LT(scan.time_s[i], 0.1f);
    widest = std::max(widest, offAxisDeg(scan.points_L[i].head<3>()));
  }
  EXPECT_LE(widest, 35.2 + 1.6);  // half the field, and the outermost laser's offset
  EXPECT_GT(widest, 33.0);

  // Seen from the pose at each point's time, every point is on the surface; from the frame's pose,
  // those late in the frame are moved by the distance driven since (about 1 m in 0.1 s), which
  // takes them off any surface but one along the drive (the road, a facade seen edge-on).
  const test::TriangleGrid grid(sim.scene().mesh.vertices, sim.scene().mesh.triangles, 1.0);
  std::size_t on = 0;
  std::size_t late = 0;
  std::size_t late_off = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < scan.points_L.size(); i += 11) {
    const Eigen::Vector3d p_L = scan.points_L[i].head<3>().cast<double>();
    const double t = sim.stamp_s(4) + scan.time_s[i];
    on += grid.nearest(sim.T_S_L_at(t) * p_L, 0.05).distance_m < 1e-3 ? 1 : 0;
    ++n;
    if (scan.time_s[i] > 0.05f) {
      ++late;
      late_off += grid.nearest(sim.T_S_L(4) * p_L, 0.05).distance_m > 0.02 ? 1 : 0;
    }
  }
  EXPECT_GT(static_cast<double>(on) / static_cast<double>(n), 0.99);
  EXPECT_GT(static_cast<double>(late_off) / static_cast<double>(late), 0.15);
}

// The number of quarter-degree cells of the field's lower half (where the road always returns) that
// points fall in, after one frame and after ten: a rosette that never retraces fills in.
TEST(SimRosette, CoverageGrowsWithIntegrationTime) {
  const Simulator& sim = aviaSim();
  std::set<std::pair<int, int>> cells;
  const auto add = [&](int frame) {
    for (const Eigen::Vector4f& p : sim.scan(frame).points_L) {
      const double left = std::atan2(p.y(), p.x()) * 180.0 / std::numbers::pi;
      const double up = std::atan2(p.z(), std::hypot(p.x(), p.y())) * 180.0 / std::numbers::pi;
      if (up < -5.0) cells.insert({static_cast<int>(std::floor(4 * left)), static_cast<int>(std::floor(4 * up))});
    }
  };
  add(0);
  const std::size_t one_frame = cells.size();
  for (int frame = 1; frame < 10; ++frame) add(frame);
  const std::size_t ten_frames = cells.size();
  std::printf("quarter-degree cells below -5 degrees: %zu after 0.1 s, %zu after 1 s\n", one_frame, ten_frames);
  EXPECT_GT(ten_frames, 2 * one_frame);
}

}  // namespace
}  // namespace artemis::sim
