// A ROS 1 bag as a recording (rosbag_dataset.hpp), read from the bag Debian's python3-rosbag writes
// for the tests: frames and stamps from the LiDAR topic, poses from the odometry chained through
// /tf_static into the LiDAR's frame, the camera's images, intrinsics and pose.

#include <gtest/gtest.h>

#include "artemis/datasets/dataset.hpp"
#include "support/test_bag.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

TEST(RosbagDataset, FramesPosesAndImagesComeFromTheirTopics) {
  test::TempDir tmp;
  ARTEMIS_WRITE_TEST_BAG(bag, tmp.path(), "lz4");
  DatasetOptions options;
  options.min_range_m = 0.0;
  options.max_range_m = 100.0;
  options.bag_topics.image = "/camera/image_raw";
  auto dataset = openDataset(bag, DatasetFormat::kAuto, options);
  ASSERT_TRUE(dataset) << dataset.status().message();
  const Dataset& d = **dataset;
  EXPECT_EQ(d.format(), "rosbag");
  ASSERT_EQ(d.size(), 10U);
  ASSERT_TRUE(d.hasPoses());
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_NEAR(d.stamp(i), 1000.0 + 0.1 * static_cast<double>(i), 1e-9);
    // base_link drives 0.5 m a frame along the odometry's x while turned 90 degrees; the LiDAR
    // sits 1.7 m above it. In the first LiDAR pose's frame that is 0.5 m a frame along -y.
    EXPECT_TRUE(d.pose(i).translation().isApprox(Eigen::Vector3d(0, -0.5 * static_cast<double>(i), 0), 1e-9) ||
                (i == 0 && d.pose(i).translation().norm() < 1e-12))
        << i << ": " << d.pose(i).translation().transpose();
    EXPECT_TRUE(d.pose(i).linear().isApprox(Eigen::Matrix3d::Identity(), 1e-9)) << i;
  }

  auto frame = d.frame(3);
  ASSERT_TRUE(frame) << frame.status().message();
  ASSERT_EQ(frame->points_L.size(), 3U);
  EXPECT_EQ(frame->points_L.points[0], Eigen::Vector3f(3, 4, 5));
  EXPECT_EQ(frame->points_L.intensity[0], 6.0f);
  EXPECT_NEAR(frame->stamp_s, 1000.3, 1e-9);
  ASSERT_EQ(frame->cameras.size(), 1U);
  const CameraView& view = frame->cameras[0];
  ASSERT_TRUE(view.hasImage());
  EXPECT_EQ(view.image.width(), 3);
  EXPECT_EQ(view.image.at(2, 1, 2), 17);
  EXPECT_DOUBLE_EQ(view.camera.fx_px, 2.0);
  EXPECT_DOUBLE_EQ(view.camera.cy_px, 0.5);
  EXPECT_TRUE(view.T_L_C.translation().isApprox(Eigen::Vector3d(0.1, 0, 0), 1e-12));
  EXPECT_TRUE((view.T_L_C.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-9));
  EXPECT_EQ(frame->stats.missing_images, 0U);

  options.frames = {2, 5};
  auto part = openDataset(bag, DatasetFormat::kRosbag, options);
  ASSERT_TRUE(part) << part.status().message();
  EXPECT_EQ((*part)->size(), 3U);
  EXPECT_EQ((*part)->firstIndex(), 2U);

  // Two image topics and none named: the camera is not guessed.
  options.bag_topics.image.clear();
  options.frames = {};
  auto unnamed = openDataset(bag, DatasetFormat::kAuto, options);
  ASSERT_TRUE(unnamed) << unnamed.status().message();
  EXPECT_TRUE((*unnamed)->cameras().empty());
}

}  // namespace
}  // namespace artemis::datasets
