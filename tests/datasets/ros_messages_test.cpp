// ROS 1 messages decoded from a bag written by Debian's python3-rosbag (tests/datasets/
// write_test_bag.py): every field as the writer set it, and damaged or unsupported messages as
// errors naming the field.

#include "artemis/datasets/ros_messages.hpp"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "artemis/datasets/rosbag_file.hpp"
#include "support/test_bag.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

// The first message of each topic of the bag.
std::map<std::string, Bytes> firstMessages(const fs::path& bag) {
  std::map<std::string, Bytes> out;
  const Status s = forEachBagMessage(bag, {}, [&](const BagMessage& m) {
    out.try_emplace(m.topic, m.data.begin(), m.data.end());
    return Status::ok();
  });
  EXPECT_TRUE(s.isOk()) << s.message();
  return out;
}

TEST(RosMessages, EveryTypeDecodesToWhatTheWriterSet) {
  test::TempDir tmp;
  ARTEMIS_WRITE_TEST_BAG(bag, tmp.path(), "none");
  auto first = firstMessages(bag);

  auto cloud = ros::decodePointCloud2(first["/velodyne_points"]);
  ASSERT_TRUE(cloud) << cloud.status().message();
  EXPECT_EQ(cloud->header.frame_id, "velodyne");
  EXPECT_DOUBLE_EQ(cloud->header.stamp_s, 1000.0);
  ASSERT_EQ(cloud->points.size(), 3U);
  ASSERT_EQ(cloud->points.intensity.size(), 3U);
  ASSERT_EQ(cloud->time_s.size(), 3U);
  EXPECT_EQ(cloud->time_field, "t");
  for (std::size_t k = 0; k < 3; ++k) {
    const auto base = static_cast<float>(4 * k);
    EXPECT_EQ(cloud->points.points[k], Eigen::Vector3f(base, base + 1, base + 2));
    EXPECT_EQ(cloud->points.intensity[k], base + 3);
    EXPECT_NEAR(cloud->time_s[k], 1e-3 * static_cast<double>(k), 1e-12);  // nanoseconds as seconds
  }

  auto image = ros::decodeImage(first["/camera/image_raw"]);
  ASSERT_TRUE(image) << image.status().message();
  EXPECT_EQ(image->encoding, "rgb8");
  ASSERT_EQ(image->rgb.width(), 3);
  ASSERT_EQ(image->rgb.height(), 2);
  EXPECT_EQ(image->rgb.at(2, 1, 0), 15);  // byte (1 * 9 + 2 * 3 + 0)
  EXPECT_EQ(image->rgb.at(2, 1, 2), 17);

  auto info = ros::decodeCameraInfo(first["/camera/camera_info"]);
  ASSERT_TRUE(info) << info.status().message();
  EXPECT_EQ(info->width, 3);
  EXPECT_EQ(info->height, 2);

  auto odometry = ros::decodeOdometry(first["/odom"]);
  ASSERT_TRUE(odometry) << odometry.status().message();
  EXPECT_EQ(odometry->header.frame_id, "odom");
  EXPECT_EQ(odometry->child_frame_id, "base_link");
  // Turned 90 degrees about z: x goes to y.
  EXPECT_TRUE((odometry->pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));

  auto tf = ros::decodeTfMessage(first["/tf_static"]);
  ASSERT_TRUE(tf) << tf.status().message();
  ASSERT_EQ(tf->size(), 2U);
  EXPECT_EQ((*tf)[0].header.frame_id, "base_link");
  EXPECT_EQ((*tf)[0].child_frame_id, "velodyne");
  EXPECT_DOUBLE_EQ((*tf)[0].T_parent_child.translation().z(), 1.7);
  EXPECT_EQ((*tf)[1].child_frame_id, "camera");
  // The camera looks along the LiDAR's x.
  EXPECT_TRUE(((*tf)[1].T_parent_child.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
}

TEST(RosMessages, DamagedOrUnsupportedMessagesAreErrorsNamingTheField) {
  test::TempDir tmp;
  ARTEMIS_WRITE_TEST_BAG(bag, tmp.path(), "none");
  auto first = firstMessages(bag);
  // Cut anywhere: an error, never a read past the end.
  const Bytes& whole = first["/velodyne_points"];
  for (std::size_t keep = 0; keep < whole.size(); ++keep) {
    const auto cut = ros::decodePointCloud2(std::span(whole.data(), keep));
    ASSERT_FALSE(cut) << keep;
    EXPECT_NE(cut.status().message().find("sensor_msgs/PointCloud2: "), std::string::npos);
  }
  const Bytes& picture = first["/camera/image_raw"];
  for (std::size_t keep = 0; keep < picture.size(); ++keep)
    ASSERT_FALSE(ros::decodeImage(std::span(picture.data(), keep)));
  const auto short_info = ros::decodeCameraInfo(std::span(first["/camera/camera_info"].data(), 40));
  ASSERT_FALSE(short_info);
  EXPECT_NE(short_info.status().message().find("sensor_msgs/CameraInfo"), std::string::npos);

  // A cloud whose data is shorter than its rows claim: width patched from 3 to 4 (offset 28 after
  // the 24-byte header with "velodyne").
  Bytes wide = whole;
  wide[28] = 4;
  const auto too_wide = ros::decodePointCloud2(wide);
  ASSERT_FALSE(too_wide);
  EXPECT_NE(too_wide.status().message().find("do not fit"), std::string::npos) << too_wide.status().message();
  // An image encoding the reader does not take.
  Bytes yuv = picture;
  const std::string rgb8 = "rgb8";
  const auto at = std::search(yuv.begin(), yuv.end(), rgb8.begin(), rgb8.end());
  ASSERT_NE(at, yuv.end());
  std::copy_n("yuv8", 4, at);
  const auto odd = ros::decodeImage(yuv);
  ASSERT_FALSE(odd);
  EXPECT_NE(odd.status().message().find("\"yuv8\""), std::string::npos) << odd.status().message();
}

}  // namespace
}  // namespace artemis::datasets
