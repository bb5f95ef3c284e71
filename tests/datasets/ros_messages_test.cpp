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
  auto imu = ros::decodeImu(first["/imu/data"]);
  ASSERT_TRUE(imu) << imu.status().message();
  EXPECT_EQ(imu->header.frame_id, "imu");
  EXPECT_FALSE(imu->has_orientation);  // all zeros, as a Livox driver leaves it
  EXPECT_DOUBLE_EQ(imu->linear_acceleration.z(), 9.81);
  EXPECT_DOUBLE_EQ(imu->angular_velocity.z(), 0.0);  // the first sample
  for (std::size_t keep = 0; keep < first["/imu/data"].size(); ++keep)
    ASSERT_FALSE(ros::decodeImu(std::span(first["/imu/data"].data(), keep))) << keep;
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

// A sensor_msgs/Image of an encoding the project's writer does not make, serialized by hand.
Bytes serializedImage(const std::string& encoding, std::uint32_t width, std::uint32_t height,
                      const std::vector<std::uint8_t>& samples) {
  Bytes out;
  const auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  const auto text = [&](const std::string& t) {
    u32(static_cast<std::uint32_t>(t.size()));
    out.insert(out.end(), t.begin(), t.end());
  };
  u32(0), u32(1000), u32(0), text("camera");  // header
  u32(height), u32(width), text(encoding);    // height, width, encoding
  out.push_back(0), u32(width);               // is_bigendian, step
  u32(static_cast<std::uint32_t>(samples.size()));
  out.insert(out.end(), samples.begin(), samples.end());
  return out;
}

// Bayer mosaics of smooth colour ramps come back as the ramps: exactly where bilinear
// interpolation is exact (inside), within the ramp's slope at the border, for all four layouts.
TEST(RosMessages, BayerImagesAreDemosaiced) {
  constexpr int w = 12;
  constexpr int h = 10;
  const auto truth = [](int u, int v, int c) { return c == 0 ? 4 * u + 20 : c == 1 ? 100 + 2 * v : 3 * v + u + 10; };
  const std::map<std::string, std::array<int, 4>> layouts = {{"bayer_rggb8", {0, 1, 1, 2}},
                                                             {"bayer_bggr8", {2, 1, 1, 0}},
                                                             {"bayer_gbrg8", {1, 2, 0, 1}},
                                                             {"bayer_grbg8", {1, 0, 2, 1}}};
  for (const auto& [encoding, tile] : layouts) {
    SCOPED_TRACE(encoding);
    std::vector<std::uint8_t> samples;
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) samples.push_back(static_cast<std::uint8_t>(truth(u, v, tile[2 * (v % 2) + u % 2])));
    }
    const auto image = ros::decodeImage(serializedImage(encoding, w, h, samples));
    ASSERT_TRUE(image) << image.status().message();
    ASSERT_EQ(image->rgb.width(), w);
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const bool inside = u > 0 && v > 0 && u < w - 1 && v < h - 1;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(image->rgb.at(u, v, c), truth(u, v, c), inside ? 0 : 4) << u << "," << v << " channel " << c;
        }
      }
    }
  }
  // Too few samples for the rows: an error naming the encoding.
  const auto short_data = ros::decodeImage(serializedImage("bayer_rggb8", w, h, std::vector<std::uint8_t>(w * h - 1)));
  ASSERT_FALSE(short_data);
  EXPECT_NE(short_data.status().message().find("bayer_rggb8"), std::string::npos) << short_data.status().message();
}

}  // namespace
}  // namespace artemis::datasets
