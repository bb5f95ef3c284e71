// ROS 1 bags as a user gives them to artemis, written by Debian's python3-rosbag: `dataset info`
// (the topic table and the topics a run reads, the same as JSON, clear errors for a topic the bag
// lacks and for a file that is not a bag), and `run FILE.bag` on a simulated street written as a
// bag, which must give the mesh of the same street read from its KITTI layout.

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "artemis/datasets/kitti_files.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/ply.hpp"
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

// A simulated street mapped from its KITTI layout, then written as a bag (its scans as PointCloud2,
// its images as CompressedImage PNGs with their CameraInfo, the run's poses as Odometry of a base
// frame, static transforms to the LiDAR and the camera) and mapped from the bag, with the
// simulator's class images as the segmenter: the same points at the same poses, so the same
// surface and the same classes; the colours differ only where the camera's pose, through a
// quaternion and back, moves a pixel boundary.
TEST(CliBag, RunOnABagMapsWhatTheRecordingItWasMadeFromMaps) {
  test::TempDir tmp;
  std::string why;
  if (test::writeTestBag(tmp.path(), "none", why).empty()) {  // the same Python modules
    if (test::runningInCi()) FAIL() << why;
    GTEST_SKIP() << why;
  }
  const auto sim = test::runCli("sim --preset demo --frames 6 --azimuth-step 0.72 --out " + (tmp / "sim").string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::string query = " --query \"cars and buildings\" --segmenter sim";
  const auto kitti = test::runCli("run " + (tmp / "sim").string() + query + " --out " + (tmp / "kitti").string());
  ASSERT_EQ(kitti.exit_code, 0) << kitti.err;
  const auto convert = [&](const std::string& name, const std::string& extra) {
    const std::string cmd = "/usr/bin/python3 " ARTEMIS_SOURCE_DIR "/tests/cli/kitti_to_bag.py " +
                            (tmp / "sim/sequences/00").string() + " " + (tmp / "kitti/trajectory.txt").string() + " " +
                            (tmp / name).string() + extra;
    return std::system(cmd.c_str());
  };
  ASSERT_EQ(convert("street.bag", ""), 0);
  const auto bag = test::runCli("run " + (tmp / "street.bag").string() + query + " --sim-gt " +
                                (tmp / "sim/gt").string() + " --out " + (tmp / "bag").string());
  ASSERT_EQ(bag.exit_code, 0) << bag.err;
  EXPECT_NE(bag.err.find("poses from /odom (6 samples), frame \"base_link\" into the LiDAR's \"velodyne\""),
            std::string::npos)
      << bag.err;
  EXPECT_NE(bag.err.find("camera /camera/image_raw/compressed (1242x375, rectified)"), std::string::npos) << bag.err;

  // The same surface: F1 at 5 cm against the KITTI layout's mesh (the 0.99).
  const auto f1 = test::runCli("eval mesh " + (tmp / "bag/mesh.ply").string() + " --gt " +
                               (tmp / "kitti/mesh.ply").string() + " --tau 0.05 --json " + (tmp / "f1.json").string());
  ASSERT_EQ(f1.exit_code, 0) << f1.err;
  EXPECT_GE(nlohmann::json::parse(test::slurp(tmp / "f1.json"))["scores"][0]["f1"].get<double>(), 0.99);
  // The same colours where a vertex lies at the same place, to within a level but for a few.
  const auto from_bag = io::readPly(tmp / "bag/mesh.ply");
  const auto from_kitti = io::readPly(tmp / "kitti/mesh.ply");
  ASSERT_TRUE(from_bag && from_kitti);
  ASSERT_EQ(from_bag->find("vertex")->count, from_kitti->find("vertex")->count);
  std::vector<bool> same_place(from_bag->find("vertex")->count, true);
  for (const char* axis : {"x", "y", "z"}) {
    const auto a = *from_bag->scalarAs<float>("vertex", axis);
    const auto b = *from_kitti->scalarAs<float>("vertex", axis);
    for (std::size_t i = 0; i < a.size(); ++i) same_place[i] = same_place[i] && a[i] == b[i];
  }
  const auto places = static_cast<std::size_t>(std::count(same_place.begin(), same_place.end(), true));
  EXPECT_GT(places, same_place.size() * 995 / 1000);  // 219 of 195,541 moved by 2 um on a 12-frame street
  std::size_t coloured = 0;
  std::size_t off_by_more_than_one = 0;
  for (const char* channel : {"red", "green", "blue"}) {
    const auto a = *from_bag->scalarAs<int>("vertex", channel);
    const auto b = *from_kitti->scalarAs<int>("vertex", channel);
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!same_place[i]) continue;
      coloured += b[i] != 0 ? 1 : 0;
      off_by_more_than_one += std::abs(a[i] - b[i]) > 1 ? 1 : 0;
    }
  }
  EXPECT_GT(coloured, places);  // the images coloured the mesh
  EXPECT_LT(off_by_more_than_one, coloured / 1000);
  const auto from_bag_poses = datasets::readPoseFile(tmp / "bag/trajectory.txt");
  const auto from_kitti_poses = datasets::readPoseFile(tmp / "kitti/trajectory.txt");
  ASSERT_TRUE(from_bag_poses && from_kitti_poses);
  ASSERT_EQ(from_bag_poses->size(), 6U);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_TRUE((*from_bag_poses)[k].isApprox((*from_kitti_poses)[k], 1e-9)) << k;
  // The same classes: per-class IoU against the simulator's labels within half a point.
  for (const char* run : {"kitti", "bag"}) {
    const auto eval = test::runCli(std::string("eval semantics ") + (tmp / run).string() + " --labels " +
                                   (tmp / "sim").string() + " --json " + (tmp / (std::string(run) + ".json")).string());
    ASSERT_EQ(eval.exit_code, 0) << eval.err;
  }
  const auto iou_kitti = nlohmann::json::parse(test::slurp(tmp / "kitti.json"))["in_frustum"]["iou"];
  const auto iou_bag = nlohmann::json::parse(test::slurp(tmp / "bag.json"))["in_frustum"]["iou"];
  for (const char* cls : {"car", "building"}) {
    EXPECT_GT(iou_kitti[cls].get<double>(), 0.8) << cls;
    EXPECT_NEAR(iou_bag[cls].get<double>(), iou_kitti[cls].get<double>(), 0.005) << cls;
  }
  const auto config = nlohmann::json::parse(test::slurp(tmp / "bag/config.json"));
  EXPECT_EQ(config["dataset"]["path"], (tmp / "street.bag").string());

  // Without the static transforms, the odometry's frame and the camera's float free: errors that
  // say so, and the camera can be left out.
  ASSERT_EQ(convert("no_tf.bag", " --no-tf"), 0);
  const auto no_tf = test::runCli("run " + (tmp / "no_tf.bag").string() + " --out " + (tmp / "x").string());
  EXPECT_EQ(no_tf.exit_code, 1);
  EXPECT_NE(no_tf.err.find("no /tf_static transform links it"), std::string::npos) << no_tf.err;
  EXPECT_NE(no_tf.err.find("--odom-topic none"), std::string::npos) << no_tf.err;
  const auto unposed =
      test::runCli("run " + (tmp / "no_tf.bag").string() + " --odom-topic none --out " + (tmp / "y").string());
  EXPECT_EQ(unposed.exit_code, 1);
  EXPECT_NE(unposed.err.find("which no /tf_static transform links to the LiDAR's"), std::string::npos) << unposed.err;
  EXPECT_NE(unposed.err.find("--image-topic none"), std::string::npos) << unposed.err;

  // A calibration file gives the camera what the bag lacks: calib.txt's P2 and Tr, written out.
  auto kitti_calib = datasets::CalibFile::read(tmp / "sim/sequences/00/calib.txt");
  ASSERT_TRUE(kitti_calib);
  const auto P2 = *kitti_calib->numbers("P2", 12);
  const auto Tr = *isometryFromRowMajor3x4(*kitti_calib->numbers("Tr", 12));
  const Eigen::Matrix4d T_L_C = Tr.inverse().matrix();
  std::vector<double> rows;  // row-major 3x4
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) rows.push_back(T_L_C(r, c));
  }
  std::ofstream(tmp / "camera.yaml") << fmt::format(
      "image_width: 1242\nimage_height: 375\nintrinsics: [{}, {}, {}, {}]\ndistortion_model: none\n"
      "distortion: []\nT_L_C: [{}]\n",
      P2[0], P2[5], P2[2], P2[6], fmt::join(rows, ", "));
  const auto calibrated = test::runCli("run " + (tmp / "no_tf.bag").string() + " --odom-topic none --calib " +
                                       (tmp / "camera.yaml").string() + " --out " + (tmp / "z").string());
  ASSERT_EQ(calibrated.exit_code, 0) << calibrated.err;
  EXPECT_NE(calibrated.err.find("calibrated by " + (tmp / "camera.yaml").string()), std::string::npos)
      << calibrated.err;
  const auto coloured_mesh = io::readPly(tmp / "z/mesh.ply");
  ASSERT_TRUE(coloured_mesh);
  const auto red = *coloured_mesh->scalarAs<int>("vertex", "red");
  EXPECT_GT(std::count_if(red.begin(), red.end(), [](int r) { return r != 0; }), static_cast<long>(red.size() / 4));
  // config.json keeps the bag's choices, so that the run's evaluations open the bag as it did
  // (without them, this bag's odometry would be refused).
  const auto z_config = nlohmann::json::parse(test::slurp(tmp / "z/config.json"));
  EXPECT_EQ(z_config["dataset"]["bag"]["odom_topic"], "none");
  EXPECT_EQ(z_config["dataset"]["bag"]["calib"], (tmp / "camera.yaml").string());
  const auto rays = test::runCli("eval rays " + (tmp / "z").string() + " --every 3 --returns 2000");
  EXPECT_EQ(rays.exit_code, 0) << rays.err;
  const auto picture = test::runCli("render " + (tmp / "z").string() + " --pose 3 -o " + (tmp / "z.png").string());
  EXPECT_EQ(picture.exit_code, 0) << picture.err;
  EXPECT_TRUE(std::filesystem::exists(tmp / "z.png"));
}

}  // namespace
}  // namespace artemis
