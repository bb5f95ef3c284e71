// The default vehicle box (--vehicle-box kitti) on the real drive: in KITTI 0013 a car follows this
// one in its lane, and what the box did not reach of it, the strip below its bumper, stood in the
// lane as a row of fins 0.1-0.2 m high wherever it had been. From 0.10 m above the road the box takes
// that strip too, and leaves the road.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/ply.hpp"
#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

// KITTI's LiDAR is mounted 1.73 m above the road.
constexpr double kMountHeightM = 1.73;

struct LaneFigures {
  std::size_t fins = 0;  // vertices in the vehicle's path 0.1-0.2 m above the road under it
  std::size_t road = 0;  // vertices in the path within 0.08 m of that road
};

// The vertices of `run`'s mesh within 0.8 m (sideways) of its path, between its first and last pose,
// by height above the road under the nearest pose.
LaneFigures laneOf(const fs::path& run) {
  LaneFigures lane;
  const auto poses = datasets::readPoseFile(run / "trajectory.txt");
  const auto mesh = io::readPly(run / "mesh.ply");
  EXPECT_TRUE(poses && mesh);
  if (!poses || !mesh || poses->size() < 3) return lane;
  const auto x = *mesh->scalarAs<float>("vertex", "x");
  const auto y = *mesh->scalarAs<float>("vertex", "y");
  const auto z = *mesh->scalarAs<float>("vertex", "z");
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::size_t nearest = 0;
    double best = 1e30;
    for (std::size_t k = 0; k < poses->size(); ++k) {
      const Eigen::Vector3d t = (*poses)[k].translation();
      const double d2 = (t.head<2>() - Eigen::Vector2d(x[i], y[i])).squaredNorm();
      if (d2 < best) {
        best = d2;
        nearest = k;
      }
    }
    if (best > 0.8 * 0.8 || nearest == 0 || nearest + 1 == poses->size()) continue;
    const double height = z[i] - ((*poses)[nearest].translation().z() - kMountHeightM);
    lane.fins += height > 0.1 && height <= 0.2 ? 1 : 0;
    lane.road += std::abs(height) < 0.08 ? 1 : 0;
  }
  return lane;
}

TEST(VehicleBoxCli, TheDefaultBoxTakesWhatAFollowingCarLeftBelowItsBumper) {
  ARTEMIS_REQUIRE_DATA("kitti_raw/reference_poses.txt");
  test::TempDir tmp;
  const std::string drive = (test::dataDir() / "kitti_raw").string();
  const std::string poses = (test::dataDir() / "kitti_raw/reference_poses.txt").string();
  const auto map = [&](const std::string& box, const fs::path& out) {
    const auto r = test::runCli("run " + drive + " --frames 30:50 --poses " + poses +
                                " --pose-refinement off --texture off --vehicle-box " + box + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return laneOf(out);
  };
  // The default, and the same box from 0.18 m up.
  const LaneFigures kitti = map("kitti", tmp / "kitti");
  const LaneFigures higher = map("-2.7,1.7,-0.8,0.8,-1.55,0", tmp / "higher");
  EXPECT_GE(higher.fins, 8u) << "the follower's strip should stand in the lane under a floor at 0.18 m";
  EXPECT_LE(kitti.fins * 4, higher.fins) << kitti.fins << " of " << higher.fins << " fins left";
  // The road in the path stays (returns within 1 %).
  EXPECT_GT(kitti.road, 2000u);
  EXPECT_NEAR(static_cast<double>(kitti.road), static_cast<double>(higher.road), 0.01 * static_cast<double>(higher.road));
}

}  // namespace
}  // namespace artemis
