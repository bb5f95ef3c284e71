#include <gtest/gtest.h>

#include <vector>

#include "artemis/core/transform.hpp"

namespace artemis {
namespace {

Isometry3d somePose() {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(1.5, -2.0, 0.25);
  return T;
}

TEST(Transform, RowMajorRoundTrip) {
  const Isometry3d T = somePose();
  const auto v = toRowMajor3x4(T);
  EXPECT_DOUBLE_EQ(v[3], 1.5);  // t_x is the 4th number (row-major 3x4)
  EXPECT_DOUBLE_EQ(v[7], -2.0);
  EXPECT_DOUBLE_EQ(v[11], 0.25);
  auto back = isometryFromRowMajor3x4(v);
  ASSERT_TRUE(back.isOk());
  EXPECT_LT((back->matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Transform, PoseAndInverseAlignBothWays) {
  const Isometry3d T = somePose();
  EXPECT_LT(((T * T.inverse()).matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(((T.inverse() * T).matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Transform, RejectsNonRigidAndWrongCount) {
  std::vector<double> scaled = {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  auto r = isometryFromRowMajor3x4(scaled);
  ASSERT_FALSE(r.isOk());
  EXPECT_NE(r.status().message().find("orthonormal"), std::string::npos);
  std::vector<double> reflection = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  EXPECT_FALSE(isometryFromRowMajor3x4(reflection).isOk());
  std::vector<double> eleven(11, 0.0);
  EXPECT_FALSE(isometryFromRowMajor3x4(eleven).isOk());
}

TEST(Transform, FormatRoundTripsThroughText) {
  const Isometry3d T = somePose();
  const std::string text = formatRowMajor3x4(T);
  std::vector<double> values;
  std::istringstream in(text);
  double v = 0;
  while (in >> v) values.push_back(v);
  ASSERT_EQ(values.size(), 12u);
  auto back = isometryFromRowMajor3x4(values);
  ASSERT_TRUE(back.isOk());
  EXPECT_LT((back->matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_NEAR(rotationAngleDeg(T), Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI, 1e-12);
}

}  // namespace
}  // namespace artemis
