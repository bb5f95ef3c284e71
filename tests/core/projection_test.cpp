#include <gtest/gtest.h>

#include "artemis/core/projection.hpp"

namespace artemis {
namespace {

// A camera looking along the LiDAR's +x axis (KITTI's mounting: camera z = LiDAR x,
// camera x = -LiDAR y, camera y = -LiDAR z).
CameraView forwardCamera() {
  CameraView view;
  view.camera = {100, 50, 50.0, 50.0, 49.5, 24.5};
  Eigen::Matrix3d R_L_C;
  R_L_C << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  view.T_L_C.linear() = R_L_C;
  return view;
}

TEST(Projection, AnalyticPixelsAndDepth) {
  PointCloud cloud;
  cloud.points = {{10, 0, 0}, {10, -2, -1}, {-10, 0, 0}, {10, 30, 0}, {0, 0, 5}};
  const auto proj = projectIntoCamera(cloud, forwardCamera());
  ASSERT_EQ(proj.size(), 2u);
  EXPECT_EQ(proj.index[0], 0u);
  EXPECT_NEAR(proj.uv_px[0].x(), 49.5, 1e-4);  // principal point
  EXPECT_NEAR(proj.uv_px[0].y(), 24.5, 1e-4);
  EXPECT_NEAR(proj.depth_m[0], 10.0, 1e-5);
  // (10, -2, -1) in LiDAR = (2, 1, 10) in camera: u = 50 * 0.2 + 49.5, v = 50 * 0.1 + 24.5.
  EXPECT_EQ(proj.index[1], 1u);
  EXPECT_NEAR(proj.uv_px[1].x(), 59.5, 1e-4);
  EXPECT_NEAR(proj.uv_px[1].y(), 29.5, 1e-4);
}

TEST(Projection, PointsBehindTheCameraAreNeverMirroredIn) {
  PointCloud cloud;
  // Behind the camera, but on its optical axis: a naive u = fx x / z would land on the centre.
  cloud.points = {{-10, 0, 0}, {-0.0001f, 0, 0}, {0, 0, 0}};
  EXPECT_EQ(projectIntoCamera(cloud, forwardCamera()).size(), 0u);
}

}  // namespace
}  // namespace artemis
