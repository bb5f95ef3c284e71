#include <gtest/gtest.h>

#include "artemis/datasets/oxts.hpp"

namespace artemis::datasets {
namespace {

TEST(Oxts, MercatorMatchesMetricDistances) {
  // Two packets 0.001 deg of latitude apart at 49 deg N: about 111.2 m north.
  OxtsPacket a{49.0, 8.4, 100.0, 0.0, 0.0, 0.0};
  OxtsPacket b{49.001, 8.4, 101.0, 0.0, 0.0, M_PI / 2};
  const auto poses = oxtsToMercatorPoses({a, b});
  const Eigen::Vector3d d = poses[1].translation() - poses[0].translation();
  EXPECT_NEAR(d.x(), 0.0, 1e-6);
  EXPECT_NEAR(d.y(), 111.2, 0.3);
  EXPECT_NEAR(d.z(), 1.0, 1e-9);
  // Yaw 90 deg: the IMU's forward axis (x) points north (y).
  EXPECT_LT((poses[1].linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
}

TEST(Oxts, LidarPosesStartAtIdentityAndApplyTheLeverArm) {
  OxtsPacket a{49.0, 8.4, 100.0, 0.0, 0.0, 0.0};
  OxtsPacket b{49.0, 8.4, 100.0, 0.0, 0.0, M_PI / 2};  // turned in place by 90 deg
  Isometry3d T_L_IMU = Isometry3d::Identity();
  T_L_IMU.translation() = Eigen::Vector3d(-1.0, 0.0, 0.0);  // LiDAR 1 m ahead of the IMU
  const auto poses = oxtsToLidarPoses({a, b}, T_L_IMU);
  EXPECT_LT((poses[0].matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-9);
  // Turning about the IMU moves the LiDAR, 1 m ahead, from (0,0) to (-1, 1) in frame L0.
  EXPECT_NEAR(poses[1].translation().x(), -1.0, 1e-6);
  EXPECT_NEAR(poses[1].translation().y(), 1.0, 1e-6);
}

}  // namespace
}  // namespace artemis::datasets
