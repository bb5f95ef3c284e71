#include "artemis/registration/icp.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>

#include "artemis/registration/odometry.hpp"
#include "scenes.hpp"

namespace artemis::registration {
namespace {

Isometry3d pose(double x, double y, double z, double yaw_deg, double roll_deg = 0.0) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(roll_deg * M_PI / 180.0, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

// The scene sampled afresh (other points on the same surfaces), seen from T_W_L, downsampled as
// the odometry does.
std::vector<Eigen::Vector3f> scanOf(const std::vector<Eigen::Vector3f>& world, const Isometry3d& T_W_L) {
  std::vector<Eigen::Vector3f> source;
  firstPointPerVoxel(test::transformed(world, T_W_L.inverse()), 0.5, source);
  return source;
}

TEST(Icp, RecoversAKnownMotion) {
  LocalMap map(LocalMapParams{});
  map.insert(test::streetCorner(1), Eigen::Vector3f::Zero());
  const Isometry3d truth = pose(0.3, -0.2, 0.05, 2.0, 0.5);
  const auto source = scanOf(test::streetCorner(2), truth);
  const IcpResult r = alignToMap(source, map, Isometry3d::Identity(), 1.0, IcpParams{});
  ASSERT_FALSE(r.used_prior);
  const Isometry3d error = truth.inverse() * r.T_W_L;
  EXPECT_LT(error.translation().norm(), 0.005) << error.translation().transpose();
  EXPECT_LT(rotationAngleDeg(error), 0.02);
  EXPECT_EQ(r.degenerate_directions, 0);
  EXPECT_LT(r.rms_m, 0.01);
}

TEST(Icp, SameResultOnOneThreadAndOnTwo) {
  LocalMap map(LocalMapParams{});
  map.insert(test::streetCorner(3), Eigen::Vector3f::Zero());
  const auto source = scanOf(test::streetCorner(4), pose(0.2, 0.1, 0.0, 1.0));
  IcpResult one, two;
  tbb::task_arena(1).execute([&] { one = alignToMap(source, map, Isometry3d::Identity(), 1.0, IcpParams{}); });
  tbb::task_arena(2).execute([&] { two = alignToMap(source, map, Isometry3d::Identity(), 1.0, IcpParams{}); });
  EXPECT_TRUE(one.T_W_L.matrix() == two.T_W_L.matrix());
  EXPECT_EQ(one.iterations, two.iterations);
}

TEST(Icp, CorridorKeepsThePriorAlongItsAxis) {
  LocalMap map(LocalMapParams{});
  map.insert(test::corridor(5), Eigen::Vector3f::Zero());
  const Isometry3d truth = pose(0.0, 0.4, 0.0, 0.0);
  const auto source = scanOf(test::corridor(6), truth);
  // The prior is off by 0.3 m along the corridor and 0.15 m across it.
  const Isometry3d prior = pose(0.3, 0.25, 0.0, 0.0);
  const IcpResult r = alignToMap(source, map, prior, 1.0, IcpParams{});
  ASSERT_FALSE(r.used_prior);
  EXPECT_GE(r.degenerate_directions, 1);
  EXPECT_NEAR(r.T_W_L.translation().x(), 0.3, 0.01);  // unobservable: the prior stands
  EXPECT_NEAR(r.T_W_L.translation().y(), 0.4, 0.01);  // observable: corrected
  EXPECT_NEAR(r.T_W_L.translation().z(), 0.0, 0.01);
}

TEST(Icp, TooFewCorrespondencesKeepThePrior) {
  LocalMap map(LocalMapParams{});
  map.insert(test::streetCorner(7), Eigen::Vector3f::Zero());
  const auto source = scanOf(test::streetCorner(8), Isometry3d::Identity());
  const Isometry3d far = pose(500.0, 0.0, 0.0, 0.0);
  const IcpResult r = alignToMap(source, map, far, 1.0, IcpParams{});
  EXPECT_TRUE(r.used_prior);
  EXPECT_TRUE(r.T_W_L.matrix() == far.matrix());
  EXPECT_TRUE(alignToMap({}, map, far, 1.0, IcpParams{}).used_prior);
}

// A scan of the corner scene from T_W_L, limited to 25 m (another sampling of the surfaces each time).
std::vector<Eigen::Vector3f> cornerScan(const Isometry3d& T_W_L, std::uint32_t seed) {
  std::vector<Eigen::Vector3f> scan;
  for (const auto& p : test::transformed(test::streetCorner(seed), T_W_L.inverse())) {
    if (p.norm() < 25.0f) scan.push_back(p);
  }
  return scan;
}

// A drive through the corner scene at 1 m a frame with a slight turn, scans limited
// to 25 m around the sensor, without any pose given: constant-velocity priors and registration alone.
TEST(Odometry, TracksADriveWithoutPoses) {
  Odometry odometry(OdometryParams{});
  Isometry3d truth = Isometry3d::Identity();
  const Isometry3d step = pose(1.0, 0.0, 0.0, 0.5);
  for (int k = 0; k < 10; ++k) {
    const Isometry3d prior = k == 0 ? Isometry3d::Identity() : odometry.predictConstantVelocity();
    const auto reg = odometry.registerScan(cornerScan(truth, 100 + static_cast<std::uint32_t>(k)), prior);
    EXPECT_FALSE(reg.fallback) << "frame " << k << ": " << reg.reason;
    const Isometry3d error = truth.inverse() * reg.T_W_L;
    EXPECT_LT(error.translation().norm(), 0.01) << "frame " << k;
    EXPECT_LT(rotationAngleDeg(error), 0.05) << "frame " << k;
    truth = truth * step;
  }
}

// Frame 3 is lost: the constant-velocity model must stay per frame across the gap.
TEST(Odometry, ConstantVelocityStaysPerFrameAcrossAGap) {
  Odometry odometry(OdometryParams{});
  const Isometry3d step = pose(1.0, 0.0, 0.0, 0.5);
  Isometry3d truth = Isometry3d::Identity();
  std::vector<Isometry3d> truths;
  for (int k = 0; k < 7; ++k) {
    truths.push_back(truth);
    truth = truth * step;
  }
  int last = -1;
  for (const int k : {0, 1, 2, 4, 5, 6}) {
    const Isometry3d prior = last < 0 ? Isometry3d::Identity() : odometry.predictConstantVelocity(k - last);
    if (k >= 2) {  // from frame 2 on the model knows the motion: its guess is already close
      const Isometry3d guess_error = truths[static_cast<std::size_t>(k)].inverse() * prior;
      EXPECT_LT(guess_error.translation().norm(), 0.05) << "frame " << k;
    }
    const auto reg =
        odometry.registerScan(cornerScan(truths[static_cast<std::size_t>(k)], 200 + static_cast<std::uint32_t>(k)),
                              prior, last < 0 ? 1 : k - last);
    EXPECT_FALSE(reg.fallback) << reg.reason;
    EXPECT_LT((truths[static_cast<std::size_t>(k)].inverse() * reg.T_W_L).translation().norm(), 0.01) << "frame " << k;
    last = k;
  }
}

TEST(Odometry, SamePosesOnOneThreadAndOnTwo) {
  std::vector<Isometry3d> poses[2];
  for (const int threads : {1, 2}) {
    OdometryParams params;
    params.threads = threads;
    Odometry odometry(params);
    Isometry3d truth = Isometry3d::Identity();
    for (int k = 0; k < 4; ++k) {
      const Isometry3d prior = k == 0 ? Isometry3d::Identity() : odometry.predictConstantVelocity();
      poses[threads - 1].push_back(
          odometry.registerScan(cornerScan(truth, 300 + static_cast<std::uint32_t>(k)), prior).T_W_L);
      truth = truth * pose(0.8, 0.1, 0.0, 1.0);
    }
  }
  for (std::size_t k = 0; k < 4; ++k) EXPECT_TRUE(poses[0][k].matrix() == poses[1][k].matrix()) << "frame " << k;
}

TEST(Odometry, RejectsBadSettingsAndNonFinitePriors) {
  OdometryParams bad;
  bad.source_voxel_m = 0.0;
  EXPECT_THROW(Odometry{bad}, std::invalid_argument);
  bad = {};
  bad.icp.min_distance_m = -1.0;
  EXPECT_THROW(Odometry{bad}, std::invalid_argument);
  bad = {};
  bad.min_distance_m = 3.0;  // above max_distance_m
  EXPECT_THROW(Odometry{bad}, std::invalid_argument);

  Odometry odometry(OdometryParams{});
  Isometry3d nan = Isometry3d::Identity();
  nan.translation().x() = NAN;
  const auto reg = odometry.registerScan(test::streetCorner(11), nan);
  EXPECT_TRUE(reg.fallback);
  EXPECT_EQ(odometry.map().pointCount(), 0u);  // nothing anchored at a broken pose
}

TEST(Odometry, AnEmptyScanKeepsThePriorAndSaysSo) {
  Odometry odometry(OdometryParams{});
  odometry.registerScan(test::streetCorner(10), Isometry3d::Identity());
  const Isometry3d prior = pose(1.0, 0.0, 0.0, 0.0);
  const auto reg = odometry.registerScan({}, prior);
  EXPECT_TRUE(reg.fallback);
  EXPECT_EQ(reg.reason, "empty scan");
  EXPECT_TRUE(reg.T_W_L.matrix() == prior.matrix());
}

TEST(FirstPointPerVoxel, KeepsTheFirstPointOfEachVoxelInOrder) {
  const std::vector<Eigen::Vector3f> points{{0.1f, 0.1f, 0.1f}, {0.2f, 0.2f, 0.2f}, {1.1f, 0.1f, 0.1f},
                                            {NAN, 0.0f, 0.0f},  {0.3f, 0.1f, 0.1f}, {-0.1f, 0.1f, 0.1f}};
  std::vector<Eigen::Vector3f> out;
  firstPointPerVoxel(points, 1.0, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0], points[0]);
  EXPECT_EQ(out[1], points[2]);
  EXPECT_EQ(out[2], points[5]);
}

}  // namespace
}  // namespace artemis::registration
