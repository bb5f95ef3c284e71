// ROS 1 bags written by Debian's python3-rosbag (tests/datasets/write_test_bag.py), uncompressed
// and with bz2 and lz4 chunks: their topics, counts, rates and messages as the reader sees them,
// the topics a run would read, and clear errors for what is not a readable bag. The writer skips
// with a message where /usr/bin/python3 cannot import rosbag, and fails under CI=true.

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "artemis/datasets/bag_topics.hpp"
#include "artemis/datasets/rosbag_file.hpp"
#include "support/test_bag.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

namespace fs = std::filesystem;

// A request naming one topic: `field` of BagTopicRequest set to `topic`.
BagTopicRequest naming(std::string BagTopicRequest::*field, const std::string& topic) {
  BagTopicRequest r;
  r.*field = topic;
  return r;
}

std::uint32_t u32At(std::span<const std::uint8_t> data, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, data.data() + at, sizeof v);
  return v;
}

TEST(Rosbag, EveryCompressionReadsTheSameTopicsCountsAndMessages) {
  test::TempDir tmp;
  for (const char* compression : {"none", "bz2", "lz4"}) {
    SCOPED_TRACE(compression);
    ARTEMIS_WRITE_TEST_BAG(bag, tmp.path(), compression);
    ASSERT_TRUE(isBagFile(bag));
    auto summary = readBagSummary(bag);
    ASSERT_TRUE(summary) << summary.status().message();
    EXPECT_EQ(summary->messages, 151U);  // 5 topics x 10, 100 IMU, 1 transform
    EXPECT_DOUBLE_EQ(summary->begin_s, 1000.0);
    EXPECT_NEAR(summary->end_s, 1000.99, 1e-9);
    ASSERT_EQ(summary->topics.size(), 7U);
    const BagTopic* lidar = summary->find("/velodyne_points");
    ASSERT_NE(lidar, nullptr);
    EXPECT_EQ(lidar->type, "sensor_msgs/PointCloud2");
    EXPECT_EQ(lidar->messages, 10U);
    EXPECT_NEAR(lidar->rateHz(), 10.0, 1e-6);
    EXPECT_NEAR(summary->find("/imu/data")->rateHz(), 100.0, 1e-6);
    EXPECT_EQ(summary->find("/tf_static")->type, "tf2_msgs/TFMessage");
    EXPECT_EQ(summary->find("/tf_static")->rateHz(), 0.0);  // one message: no rate

    // The LiDAR's messages, in time order, as serialized: header seq, stamp, frame "velodyne",
    // then height 1 and width 3.
    std::vector<double> stamps;
    Status s = forEachBagMessage(bag, {"/velodyne_points"}, [&](const BagMessage& m) {
      EXPECT_EQ(m.topic, "/velodyne_points");
      EXPECT_EQ(u32At(m.data, 0), stamps.size());  // seq
      EXPECT_EQ(u32At(m.data, 4), 1000U);          // stamp.secs
      EXPECT_EQ(u32At(m.data, 12), 8U);            // frame_id's length
      EXPECT_EQ(std::string(reinterpret_cast<const char*>(m.data.data()) + 16, 8), "velodyne");
      EXPECT_EQ(u32At(m.data, 24), 1U);
      EXPECT_EQ(u32At(m.data, 28), 3U);
      stamps.push_back(m.stamp_s);
      return Status::ok();
    });
    ASSERT_TRUE(s.isOk()) << s.message();
    ASSERT_EQ(stamps.size(), 10U);
    for (std::size_t i = 0; i < stamps.size(); ++i) EXPECT_NEAR(stamps[i], 1000.0 + 0.1 * static_cast<double>(i), 1e-9);
    // An error from the visitor stops the reading and comes back.
    std::size_t seen = 0;
    s = forEachBagMessage(bag, {},
                          [&](const BagMessage&) { return ++seen == 3 ? invalidArgument("enough") : Status::ok(); });
    EXPECT_EQ(s.message(), "enough");
    EXPECT_EQ(seen, 3U);
  }
}

TEST(Rosbag, TopicsAreChosenWhenOnlyOneFitsOrWhenNamed) {
  test::TempDir tmp;
  ARTEMIS_WRITE_TEST_BAG(bag, tmp.path(), "lz4");
  const auto summary = readBagSummary(bag);
  ASSERT_TRUE(summary) << summary.status().message();
  auto choice = chooseBagTopics(*summary, {});
  ASSERT_TRUE(choice) << choice.status().message();
  EXPECT_EQ(choice->lidar.topic, "/velodyne_points");
  EXPECT_EQ(choice->imu.topic, "/imu/data");
  EXPECT_EQ(choice->odometry.topic, "/odom");
  // Raw and compressed images: no choice, and the reason names both and the flag.
  EXPECT_TRUE(choice->image.topic.empty());
  EXPECT_EQ(choice->image.candidates.size(), 2U);
  EXPECT_NE(choice->image.why.find("/camera/image_raw/compressed"), std::string::npos) << choice->image.why;
  EXPECT_NE(choice->image.why.find("--image-topic"), std::string::npos) << choice->image.why;
  // Named, either way; the CameraInfo beside it is /camera/camera_info.
  for (const char* image : {"/camera/image_raw", "/camera/image_raw/compressed"}) {
    choice = chooseBagTopics(*summary, naming(&BagTopicRequest::image, image));
    ASSERT_TRUE(choice) << choice.status().message();
    EXPECT_EQ(choice->image.topic, image);
    EXPECT_EQ(choice->camera_info.topic, "/camera/camera_info");
    EXPECT_EQ(choice->camera_info.why, "beside the image topic");
  }
  // A topic the bag lacks, or of a type the role does not read: errors naming the bag's candidates.
  auto missing = chooseBagTopics(*summary, naming(&BagTopicRequest::lidar, "/points"));
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.status().message().find("--lidar-topic /points"), std::string::npos);
  EXPECT_NE(missing.status().message().find("/velodyne_points"), std::string::npos) << missing.status().message();
  auto wrong = chooseBagTopics(*summary, naming(&BagTopicRequest::imu, "/odom"));
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.status().message().find("holds nav_msgs/Odometry"), std::string::npos) << wrong.status().message();
}

TEST(Rosbag, SeveralLidarsWaitForAName) {
  BagSummary summary;
  summary.path = "rig.bag";
  summary.topics = {{"/livox/lidar", "livox_ros_driver/CustomMsg", 100, 0.0, 9.9},
                    {"/velodyne_points", "sensor_msgs/PointCloud2", 100, 0.0, 9.9}};
  auto choice = chooseBagTopics(summary, {});
  ASSERT_TRUE(choice);
  EXPECT_TRUE(choice->lidar.topic.empty());
  EXPECT_NE(choice->lidar.why.find("2 candidates"), std::string::npos) << choice->lidar.why;
  EXPECT_EQ(choice->image.why, "no sensor_msgs/Image, sensor_msgs/CompressedImage topic");
  choice = chooseBagTopics(summary, naming(&BagTopicRequest::lidar, "/livox/lidar"));
  ASSERT_TRUE(choice);
  EXPECT_EQ(choice->lidar.topic, "/livox/lidar");
  EXPECT_EQ(choice->lidar.why, "named with --lidar-topic");
}

TEST(Rosbag, WhatIsNotAReadableBagIsAClearError) {
  test::TempDir tmp;
  ARTEMIS_WRITE_TEST_BAG(bag, tmp.path(), "lz4");
  const auto message = [](const fs::path& p) {
    auto s = readBagSummary(p);
    return s ? std::string("read") : s.status().message();
  };
  EXPECT_NE(message(tmp.path() / "absent.bag").find("no such file"), std::string::npos);
  std::ofstream(tmp.path() / "text.bag") << "not a bag\n";
  EXPECT_FALSE(isBagFile(tmp.path() / "text.bag"));
  EXPECT_NE(message(tmp.path() / "text.bag").find("not a ROS 1 bag"), std::string::npos);
  // Cut short anywhere: the header, the middle, or just the index at the end.
  std::ifstream in(bag, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const std::size_t keep : {std::size_t{20}, bytes.size() / 2, bytes.size() - 100}) {
    const fs::path cut = tmp.path() / ("cut_" + std::to_string(keep) + ".bag");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(keep));
    const std::string m = message(cut);
    EXPECT_NE(m.find(cut.string()), std::string::npos) << m;
    EXPECT_NE(m, "read") << "kept " << keep << " of " << bytes.size() << " bytes";
    EXPECT_NE(m.find("ends early"), std::string::npos) << m;
    EXPECT_NE(m.find("rosbag reindex"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace artemis::datasets
