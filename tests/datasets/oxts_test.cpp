#include <gtest/gtest.h>

#include "artemis/datasets/oxts.hpp"

#include <fstream>

#include "support/test_support.hpp"

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

// Every angle and position is range-checked: one packet with a longitude of 1e300 would otherwise
// move the whole trajectory across the planet without an error.
TEST(Oxts, FieldsOutOfTheirRangeAreErrorsNamingTheField) {
  test::TempDir dir;
  const std::string rest = " 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n";
  const auto read = [&](const std::string& first_six) {
    std::ofstream(dir / "0000000000.txt") << first_six << rest;
    return readOxtsFile(dir / "0000000000.txt");
  };
  ASSERT_TRUE(read("49.0 8.4 110 0.01 -0.02 1.5").isOk());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"49.0 1e300 110 0 0 0", "longitude (degrees) 1e+300 is out of range"},
      {"49.0 -180.5 110 0 0 0", "longitude (degrees) -180.5"},
      {"49.0 8.4 1e300 0 0 0", "altitude (m) 1e+300 is out of range"},
      {"49.0 8.4 -5000 0 0 0", "altitude (m) -5000"},
      {"90 8.4 110 0 0 0", "latitude (degrees) 90 is out of range"},
      {"49.0 8.4 110 7 0 0", "roll (rad) 7"},
      {"49.0 8.4 110 0 -7 0", "pitch (rad) -7"},
      {"49.0 8.4 110 0 0 100", "yaw (rad) 100 is out of range"},
      {"49.0 8.4 nan 0 0 0", "field 3 (lat lon alt roll pitch yaw) is not finite"},
  };
  for (const auto& [fields, message] : cases) {
    SCOPED_TRACE(fields);
    auto packet = read(fields);
    ASSERT_FALSE(packet.isOk());
    EXPECT_NE(packet.status().message().find("0000000000.txt line 1"), std::string::npos) << packet.status().message();
    EXPECT_NE(packet.status().message().find(message), std::string::npos) << packet.status().message();
  }
}

}  // namespace
}  // namespace artemis::datasets
