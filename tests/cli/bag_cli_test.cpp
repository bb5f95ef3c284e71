// artemis dataset info FILE.bag as a user runs it, on a bag written by Debian's python3-rosbag:
// the topic table and the topics a run reads, the same as JSON, and clear errors for a topic the
// bag lacks and for a file that is not a bag.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.hpp"
#include "support/test_bag.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

TEST(CliBag, InfoListsTopicsAndWhatARunReads) {
  test::TempDir tmp;
  ARTEMIS_WRITE_TEST_BAG(bag, tmp.path(), "bz2");
  const auto table = test::runCli("dataset info " + bag.string());
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("ROS 1 bag"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("151 messages on 7 topics"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("/imu/data"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("100.00"), std::string::npos) << table.out;  // the IMU's rate
  EXPECT_NE(table.out.find("--image-topic"), std::string::npos) << table.out;

  const auto json = test::runCli("dataset info " + bag.string() + " --json --image-topic /camera/image_raw");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["format"], "rosbag");
  EXPECT_EQ(j["messages"], 151);
  EXPECT_NEAR(j["duration_s"].get<double>(), 0.99, 1e-9);
  EXPECT_EQ(j["topics"].size(), 7U);
  EXPECT_EQ(j["chosen"]["lidar"]["topic"], "/velodyne_points");
  EXPECT_EQ(j["chosen"]["image"]["topic"], "/camera/image_raw");
  EXPECT_EQ(j["chosen"]["image"]["why"], "named with --image-topic");
  EXPECT_EQ(j["chosen"]["camera_info"]["topic"], "/camera/camera_info");
  EXPECT_EQ(j["chosen"]["image"]["candidates"].size(), 2U);

  const auto missing = test::runCli("dataset info " + bag.string() + " --lidar-topic /points");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("has no topic /points"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find(bag.string()), std::string::npos) << missing.err;

  std::ofstream(tmp / "notes.bag") << "hello\n";
  const auto text = test::runCli("dataset info " + (tmp / "notes.bag").string());
  EXPECT_EQ(text.exit_code, 1);
  EXPECT_NE(text.err.find("not a ROS 1 bag"), std::string::npos) << text.err;
  const auto absent = test::runCli("dataset info " + (tmp / "absent.bag").string());
  EXPECT_EQ(absent.exit_code, 1);
  EXPECT_NE(absent.err.find("no such file"), std::string::npos) << absent.err;
}

}  // namespace
}  // namespace artemis
