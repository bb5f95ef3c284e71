// Bags written by ARTEMIS's BagWriter (the ROS message packages' own types): every message reads
// back through the project's decoders as it was given, under each compression; Debian's
// python3-rosbag deserializes every message by the bag's type names and MD5 sums (so rosbag,
// rqt_bag and the peers' tools read these bags too); and what a writer refuses, it says.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "artemis/datasets/ros_messages.hpp"
#include "artemis/datasets/rosbag_file.hpp"
#include "artemis/datasets/rosbag_writer.hpp"
#include "support/test_bag.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

namespace fs = std::filesystem;

Isometry3d pose(double yaw, const Eigen::Vector3d& t) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

ros::PointCloud2 cloud(double stamp_s) {
  ros::PointCloud2 c;
  c.header.seq = 7;
  c.header.stamp_s = stamp_s;
  c.header.frame_id = "velodyne";
  for (int i = 0; i < 50; ++i) {
    c.points.points.emplace_back(0.5f * static_cast<float>(i), -1.0f, 0.25f);
    c.points.intensity.push_back(static_cast<float>(i) / 50.0f);
    c.time_s.push_back(0.002 * i);
  }
  return c;
}

ros::Header header(std::uint32_t seq, double stamp_s, const char* frame) {
  ros::Header h;
  h.seq = seq;
  h.stamp_s = stamp_s;
  h.frame_id = frame;
  return h;
}

// One of each message the writer takes, at 1000.25 s.
void writeOneOfEach(BagWriter& bag) {
  constexpr double t = 1000.25;
  ASSERT_TRUE(bag.write("/velodyne_points", cloud(t)).isOk());
  ros::ImageMessage image;
  image.header = header(1, t, "camera");
  image.rgb = ImageU8(4, 3, 3);
  for (std::size_t i = 0; i < image.rgb.data().size(); ++i) image.rgb.data()[i] = static_cast<std::uint8_t>(10 * i);
  ASSERT_TRUE(bag.write("/camera/image_raw", image).isOk());
  ros::CompressedImage compressed;
  compressed.header = header(1, t, "camera");
  compressed.format = "png";
  compressed.data = {1, 2, 3};
  ASSERT_TRUE(bag.write("/camera/image_raw/compressed", compressed).isOk());
  ros::CameraInfo info;
  info.header = header(1, t, "camera");
  info.width = 4;
  info.height = 3;
  info.distortion_model = "plumb_bob";
  info.D = {-0.07616, 0.123001, -0.00113, 0.000251, 0.0};
  info.K = {1293.57, 0, 626.91, 0, 1293.32, 522.80, 0, 0, 1};
  info.P = {1293.57, 0, 626.91, 0, 0, 1293.32, 522.80, 0, 0, 0, 1, 0};
  ASSERT_TRUE(bag.write("/camera/camera_info", info).isOk());
  ros::Odometry odometry;
  odometry.header = header(2, t, "odom");
  odometry.child_frame_id = "base_link";
  odometry.pose = pose(0.3, {1, 2, 3});
  ASSERT_TRUE(bag.write("/odom", odometry).isOk());
  ros::Imu imu;
  imu.header = header(3, t, "imu_link");
  imu.has_orientation = false;
  imu.angular_velocity = {0.0, 0.0, 0.5};
  imu.linear_acceleration = {0.1, 0.0, 9.81};
  ASSERT_TRUE(bag.write("/imu/data", imu).isOk());
  std::vector<ros::Transform> transforms(1);
  transforms[0].header = header(0, t, "base_link");
  transforms[0].child_frame_id = "velodyne";
  transforms[0].T_parent_child = pose(0.0, {0, 0, 1.73});
  ASSERT_TRUE(bag.write("/tf_static", transforms).isOk());
}

TEST(BagWriter, EveryMessageReadsBackAsGivenUnderEachCompression) {
  test::TempDir tmp;
  for (const char* name : {"none", "bz2", "lz4"}) {
    SCOPED_TRACE(name);
    const fs::path path = tmp / (std::string(name) + ".bag");
    auto bag = BagWriter::create(path, parseBagCompression(name).value());
    ASSERT_TRUE(bag) << bag.status().message();
    writeOneOfEach(**bag);
    ASSERT_TRUE((*bag)->close().isOk());
    EXPECT_FALSE(fs::exists(path.string() + ".part"));
    auto summary = readBagSummary(path);
    ASSERT_TRUE(summary) << summary.status().message();
    EXPECT_EQ(summary->messages, 7U);
    EXPECT_DOUBLE_EQ(summary->begin_s, 1000.25);
    EXPECT_EQ(summary->find("/imu/data")->type, "sensor_msgs/Imu");
    std::map<std::string, int> seen;
    const Status read = forEachBagMessage(path, {}, [&](const BagMessage& m) {
      ++seen[m.topic];
      if (m.topic == "/velodyne_points") {
        auto c = ros::decodePointCloud2(m.data);
        EXPECT_TRUE(c) << c.status().message();
        const ros::PointCloud2 given = cloud(1000.25);
        EXPECT_EQ(c->header.seq, 7U);
        EXPECT_DOUBLE_EQ(c->header.stamp_s, 1000.25);
        EXPECT_EQ(c->time_field, "time");
        EXPECT_EQ(c->points.points, given.points.points);
        EXPECT_EQ(c->points.intensity, given.points.intensity);
        for (std::size_t i = 0; i < given.time_s.size(); ++i) EXPECT_NEAR(c->time_s[i], given.time_s[i], 1e-7);
      } else if (m.topic == "/camera/image_raw") {
        auto im = ros::decodeImage(m.data);
        EXPECT_TRUE(im) << im.status().message();
        EXPECT_EQ(im->rgb.at(3, 2, 2), static_cast<std::uint8_t>(10 * 35));
      } else if (m.topic == "/camera/image_raw/compressed") {
        EXPECT_EQ(ros::decodeCompressedImage(m.data)->data, (std::vector<std::uint8_t>{1, 2, 3}));
      } else if (m.topic == "/camera/camera_info") {
        auto info = ros::decodeCameraInfo(m.data);
        EXPECT_EQ(info->D.size(), 5U);
        EXPECT_DOUBLE_EQ(info->D[0], -0.07616);
        EXPECT_DOUBLE_EQ(info->K[5], 522.80);
      } else if (m.topic == "/odom") {
        auto o = ros::decodeOdometry(m.data);
        EXPECT_EQ(o->child_frame_id, "base_link");
        EXPECT_TRUE(o->pose.isApprox(pose(0.3, {1, 2, 3}), 1e-12));
      } else if (m.topic == "/imu/data") {
        auto imu = ros::decodeImu(m.data);
        EXPECT_TRUE(imu) << imu.status().message();
        EXPECT_FALSE(imu->has_orientation);
        EXPECT_DOUBLE_EQ(imu->angular_velocity.z(), 0.5);
        EXPECT_DOUBLE_EQ(imu->linear_acceleration.z(), 9.81);
      } else {
        auto tf = ros::decodeTfMessage(m.data);
        EXPECT_EQ(tf->size(), 1U);
        EXPECT_EQ(tf->front().child_frame_id, "velodyne");
      }
      return Status::ok();
    });
    ASSERT_TRUE(read.isOk()) << read.message();
    EXPECT_EQ(seen.size(), 7U);
  }
}

TEST(BagWriter, PythonRosbagDeserializesEveryMessage) {
  test::TempDir tmp;
  std::string why;
  if (test::writeTestBag(tmp.path(), "none", why).empty()) {  // probes the same Python modules
    if (test::runningInCi()) FAIL() << why;
    GTEST_SKIP() << why;
  }
  const fs::path path = tmp / "ours.bag";
  auto bag = BagWriter::create(path, BagCompression::kLz4);
  ASSERT_TRUE(bag);
  writeOneOfEach(**bag);
  ASSERT_TRUE((*bag)->close().isOk());
  const std::string text = test::readBagWithPython(path);
  ASSERT_FALSE(text.empty());
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j.size(), 7U) << j.dump();
  const auto& lidar = j["/velodyne_points"];
  EXPECT_EQ(lidar["type"], "sensor_msgs/PointCloud2");
  EXPECT_EQ(lidar["first"]["fields"], nlohmann::json::parse(R"(["x","y","z","intensity","time"])"));
  EXPECT_EQ(lidar["first"]["point_step"], 20);
  EXPECT_EQ(lidar["first"]["width"], 50);
  EXPECT_DOUBLE_EQ(lidar["stamp"].get<double>(), 1000.25);
  EXPECT_EQ(j["/camera/image_raw"]["first"]["encoding"], "rgb8");
  EXPECT_EQ(j["/camera/image_raw"]["first"]["first"], nlohmann::json::parse("[0,10,20]"));
  EXPECT_EQ(j["/camera/image_raw/compressed"]["first"]["bytes"], 3);
  EXPECT_DOUBLE_EQ(j["/camera/camera_info"]["first"]["K"][0].get<double>(), 1293.57);
  EXPECT_DOUBLE_EQ(j["/odom"]["first"]["position"][2].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["/imu/data"]["first"]["orientation_covariance0"].get<double>(), -1.0);
  EXPECT_EQ(j["/tf_static"]["first"]["children"][0], "velodyne");
}

TEST(BagWriter, RefusesWhatABagCannotHoldAndLeavesNoHalfBag) {
  test::TempDir tmp;
  EXPECT_FALSE(parseBagCompression("zstd"));
  const auto missing = BagWriter::create(tmp / "no" / "such" / "folder.bag");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.status().message().find("folder.bag.part"), std::string::npos) << missing.status().message();
  {
    auto bag = BagWriter::create(tmp / "half.bag");
    ASSERT_TRUE(bag);
    const Status at_zero = (*bag)->write("/velodyne_points", cloud(0.0));
    EXPECT_FALSE(at_zero.isOk());
    EXPECT_NE(at_zero.message().find("/velodyne_points"), std::string::npos) << at_zero.message();
    ros::PointCloud2 uneven = cloud(1000.0);
    uneven.time_s.pop_back();
    const Status times = (*bag)->write("/velodyne_points", uneven);
    EXPECT_FALSE(times.isOk());
    EXPECT_NE(times.message().find("49 point times for 50 points"), std::string::npos) << times.message();
    ASSERT_TRUE((*bag)->write("/velodyne_points", cloud(1000.0)).isOk());
    EXPECT_TRUE(fs::exists(tmp / "half.bag.part"));
  }  // destroyed without close(): nothing is left
  EXPECT_FALSE(fs::exists(tmp / "half.bag"));
  EXPECT_FALSE(fs::exists(tmp / "half.bag.part"));
}

}  // namespace
}  // namespace artemis::datasets
