// `artemis sim --format rosbag`: the simulated street written as a ROS 1 bag by ARTEMIS's own
// writer (PointCloud2 with per-point time, images, CameraInfo, exact odometry, a 100 Hz IMU,
// static transforms), which Debian's python3-rosbag reads, and which maps as the same street's
// KITTI layout does: the same surface and the same classes.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "artemis/io/ply.hpp"
#include "cli_run.hpp"
#include "support/test_bag.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

TEST(CliSimBag, TheStreetAsABagMapsAsItsKittiLayout) {
  test::TempDir tmp;
  const std::string street = "sim --preset demo --frames 6 --azimuth-step 0.72";
  const auto bag_sim = test::runCli(street + " --format rosbag --out " + (tmp / "bag").string());
  ASSERT_EQ(bag_sim.exit_code, 0) << bag_sim.err;
  EXPECT_NE(bag_sim.out.find("a ROS 1 bag"), std::string::npos) << bag_sim.out;
  EXPECT_TRUE(std::filesystem::exists(tmp / "bag/gt/mesh.ply"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "bag/gt/semantic_2/000005.png"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "bag/sequences"));
  const auto kitti_sim = test::runCli(street + " --out " + (tmp / "kitti").string());
  ASSERT_EQ(kitti_sim.exit_code, 0) << kitti_sim.err;

  const std::string bag = (tmp / "bag/street.bag").string();
  const auto info = test::runCli("dataset info " + bag + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["messages"], 6 * 4 + 60 + 1);  // cloud, image, CameraInfo, odometry a frame; the IMU; tf
  EXPECT_EQ(j["chosen"]["imu"]["topic"], "/imu/data");
  EXPECT_EQ(j["chosen"]["image"]["topic"], "/camera/image_raw/compressed");

  // Any ROS tool reads it: python3-rosbag deserializes every message by its type and MD5 sum.
  const std::string python = test::readBagWithPython(bag);
  if (python.empty() && !test::runningInCi()) GTEST_SKIP() << "/usr/bin/python3 cannot read bags (python3-rosbag)";
  ASSERT_FALSE(python.empty());
  const auto topics = nlohmann::json::parse(python);
  EXPECT_EQ(topics["/velodyne_points"]["first"]["fields"],
            nlohmann::json::parse(R"(["x","y","z","intensity","time"])"));
  EXPECT_EQ(topics["/imu/data"]["count"], 60);
  // The IMU at rest in the first frame reads gravity (the car accelerates gently along x).
  EXPECT_NEAR(topics["/imu/data"]["first"]["linear_acceleration"][2].get<double>(), 9.80665, 1e-3);

  const std::string query = " --query \"cars and buildings\" --segmenter sim --checkpoint-every 0";
  const auto from_kitti = test::runCli("run " + (tmp / "kitti").string() + query + " --out " + (tmp / "rk").string());
  ASSERT_EQ(from_kitti.exit_code, 0) << from_kitti.err;
  const auto from_bag =
      test::runCli("run " + bag + query + " --sim-gt " + (tmp / "bag/gt").string() + " --out " + (tmp / "rb").string());
  ASSERT_EQ(from_bag.exit_code, 0) << from_bag.err;
  EXPECT_NE(from_bag.err.find("poses from /odom (6 samples), frame \"base_link\" into the LiDAR's \"velodyne\""),
            std::string::npos)
      << from_bag.err;
  const auto f1 = test::runCli("eval mesh " + (tmp / "rb/mesh.ply").string() + " --gt " +
                               (tmp / "rk/mesh.ply").string() + " --tau 0.05 --json " + (tmp / "f1.json").string());
  ASSERT_EQ(f1.exit_code, 0) << f1.err;
  EXPECT_GE(nlohmann::json::parse(test::slurp(tmp / "f1.json"))["scores"][0]["f1"].get<double>(), 0.99);
  const auto mesh_bag = io::readPly(tmp / "rb/mesh.ply");
  const auto mesh_kitti = io::readPly(tmp / "rk/mesh.ply");
  ASSERT_TRUE(mesh_bag && mesh_kitti);
  EXPECT_EQ(mesh_bag->find("face")->count, mesh_kitti->find("face")->count);
  for (const char* run : {"rk", "rb"}) {
    const auto eval =
        test::runCli(std::string("eval semantics ") + (tmp / run).string() + " --labels " + (tmp / "kitti").string() +
                     " --json " + (tmp / (std::string(run) + ".json")).string());
    ASSERT_EQ(eval.exit_code, 0) << eval.err;
  }
  const auto iou_kitti = nlohmann::json::parse(test::slurp(tmp / "rk.json"))["in_frustum"]["iou"];
  const auto iou_bag = nlohmann::json::parse(test::slurp(tmp / "rb.json"))["in_frustum"]["iou"];
  for (const char* cls : {"car", "building"}) {
    EXPECT_GT(iou_kitti[cls].get<double>(), 0.8) << cls;
    EXPECT_NEAR(iou_bag[cls].get<double>(), iou_kitti[cls].get<double>(), 0.005) << cls;
  }
}

TEST(CliSimBag, RawImagesAndBz2Chunks) {
  test::TempDir tmp;
  const auto sim = test::runCli(
      "sim --preset demo --frames 2 --azimuth-step 1.44 --format rosbag --bag-images raw "
      "--bag-compression bz2 --out " +
      (tmp / "s").string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::string bag = (tmp / "s/street.bag").string();
  const auto run = test::runCli("run " + bag + " --checkpoint-every 0 --out " + (tmp / "r").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("camera /camera/image_raw (1242x375, rectified)"), std::string::npos) << run.err;
  const auto again = test::runCli("sim --preset demo --frames 2 --format rosbag --out " + (tmp / "s").string());
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  const auto bad =
      test::runCli("sim --preset demo --frames 2 --format rosbag --bag-compression zstd --out " + (tmp / "t").string());
  EXPECT_NE(bad.exit_code, 0);
  const auto avia_kitti = test::runCli("sim --preset demo --frames 2 --lidar avia --out " + (tmp / "u").string());
  EXPECT_EQ(avia_kitti.exit_code, 1);
  EXPECT_NE(avia_kitti.err.find("use --format rosbag"), std::string::npos) << avia_kitti.err;
}

// The Avia-like rosette, written with each point's time and seen from the pose at that time as the
// rig drives 10 m/s: mapped with the exact odometry, the map is blurred by up to a metre of motion
// per frame unless --deskew moves each point by its time.
TEST(CliSimBag, AviaRosetteIsDeskewedByItsPointTimes) {
  test::TempDir tmp;
  const auto sim =
      test::runCli("sim --preset demo --frames 20 --lidar avia --format rosbag --out " + (tmp / "avia").string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::string bag = (tmp / "avia/street.bag").string();
  const auto seen = test::runCli("dataset export-cloud " + bag + " --voxel 0.05 -o " + (tmp / "seen.ply").string());
  ASSERT_EQ(seen.exit_code, 0) << seen.err;
  double precision[2] = {0.0, 0.0};
  double f1[2] = {0.0, 0.0};
  for (int deskew = 0; deskew < 2; ++deskew) {
    const std::string out = (tmp / ("run" + std::to_string(deskew))).string();
    const auto run = test::runCli("run " + bag + " --texture off --checkpoint-every 0" +
                                  (deskew != 0 ? " --deskew" : "") + " --out " + out);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::string json = out + ".json";
    const auto eval = test::runCli("eval mesh " + out + "/mesh.ply --gt " + (tmp / "avia/gt/mesh.ply").string() +
                                   " --seen " + (tmp / "seen.ply").string() + " --tau 0.05 --json " + json);
    ASSERT_EQ(eval.exit_code, 0) << eval.err;
    const auto score = nlohmann::json::parse(test::slurp(json))["scores"][0];
    precision[deskew] = score["precision"].get<double>();
    f1[deskew] = score["f1"].get<double>();
  }
  // Measured: precision 0.66 -> 0.95, F1 0.54 -> 0.78 on these 20 frames.
  EXPECT_LT(precision[0], 0.8);
  EXPECT_GT(precision[1], 0.9);
  EXPECT_GT(f1[1], f1[0] + 0.15);
}

}  // namespace
}  // namespace artemis
