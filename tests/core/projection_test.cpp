#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

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

TEST(Projection, DepthProjectionKeepsTheNearestDepthPerPixel) {
  PointCloud cloud;
  // Two points on the principal point's pixel (10 m and 6 m), one at (59.5, 29.5), one behind.
  cloud.points = {{10, 0, 0}, {6, 0, 0}, {10, -2, -1}, {-10, 0, 0}};
  DepthProjection out;
  projectDepth(cloud, forwardCamera(), 100, 50, out);
  ASSERT_EQ(out.points.size(), 3u);
  EXPECT_EQ(out.points[0].index, 0u);
  EXPECT_EQ(out.points[0].pixel, 25u * 100u + 50u);  // (49.5, 24.5): halves round up, floor(x + 0.5)
  EXPECT_FLOAT_EQ(out.nearest.at(50, 25), 6.0f);
  EXPECT_FLOAT_EQ(out.nearest.at(60, 30), 10.0f);
  EXPECT_TRUE(std::isinf(out.nearest.at(0, 0)));
  // Storage is reused: a second, empty frame leaves nothing behind.
  projectDepth(PointCloud{}, forwardCamera(), 100, 50, out);
  EXPECT_TRUE(out.points.empty());
  EXPECT_TRUE(std::isinf(out.nearest.at(50, 25)));
}

TEST(Projection, MinFilterTakesTheLeastOfEachWindow) {
  ImageF32 image(7, 5, 1, 9.0f);
  image.at(3, 2) = 1.0f;
  image.at(0, 0) = 2.0f;
  minFilter(image, 1);
  for (int v = 0; v < 5; ++v) {
    for (int u = 0; u < 7; ++u) {
      float expected = 9.0f;
      if (std::abs(u - 3) <= 1 && std::abs(v - 2) <= 1)
        expected = 1.0f;
      else if (u <= 1 && v <= 1)
        expected = 2.0f;
      EXPECT_FLOAT_EQ(image.at(u, v), expected) << u << " " << v;
    }
  }
}

TEST(Projection, MinFilterMatchesTheWindowsLeastEverywhere) {
  // Random depths (some far, as where no return fell) against the least of each clipped window,
  // for radii up to one wider than the image is tall.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> depth(0.5f, 80.0f);
  std::bernoulli_distribution empty(0.3);
  for (const int r : {1, 2, 3, 9}) {
    ImageF32 image(13, 8, 1, 0.0f);
    for (float& x : image.data()) x = empty(rng) ? std::numeric_limits<float>::infinity() : depth(rng);
    const ImageF32 before = image;
    minFilter(image, r);
    for (int v = 0; v < image.height(); ++v) {
      for (int u = 0; u < image.width(); ++u) {
        float least = std::numeric_limits<float>::infinity();
        for (int y = std::max(0, v - r); y <= std::min(image.height() - 1, v + r); ++y) {
          for (int x = std::max(0, u - r); x <= std::min(image.width() - 1, u + r); ++x) {
            least = std::min(least, before.at(x, y));
          }
        }
        ASSERT_EQ(image.at(u, v), least) << "r " << r << " at " << u << " " << v;
      }
    }
  }
}

}  // namespace
}  // namespace artemis
