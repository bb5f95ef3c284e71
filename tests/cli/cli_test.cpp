// The artemis CLI as a user runs it: exit codes, --json output, files written.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "artemis/io/ply.hpp"
#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

using test::RunResult;

RunResult run(const std::string& args) {
  return test::runCli(args);
}

std::string rawPath() {
  return (test::dataDir() / "kitti_raw").string();
}

TEST(Cli, HelpExplainsTheSubcommands) {
  const auto r = run("dataset info --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--frames", "--min-range", "--max-range", "--vertical-correction", "--json", "--poses"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  }
  EXPECT_NE(run("--help").out.find("dataset"), std::string::npos);
}

TEST(Cli, DatasetInfoJsonOnKittiRaw) {
  ARTEMIS_REQUIRE_DATA("kitti_raw");
  const auto r = run("dataset info " + rawPath() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format"], "kitti-raw");
  EXPECT_EQ(j["frames"], 50);
  EXPECT_GT(j["points_per_frame"]["min"].get<int>(), 100000);
  EXPECT_GE(j["points_per_frame"]["median"].get<int>(), j["points_per_frame"]["min"].get<int>());
  EXPECT_LT(j["points_per_frame"]["max"].get<int>(), 140000);
  EXPECT_EQ(j["image_size"], nlohmann::json::array({1242, 375}));
  // 49 steps of 1.0-1.5 m.
  EXPECT_GT(j["path_length_m"].get<double>(), 49.0);
  EXPECT_LT(j["path_length_m"].get<double>(), 73.5);
  EXPECT_NEAR(j["projected_share"].get<double>(), 0.15, 0.02);
}

TEST(Cli, ExportCloudWritesAReadablePly) {
  ARTEMIS_REQUIRE_DATA("kitti_raw");
  test::TempDir tmp;
  const auto out = (tmp / "cloud.ply").string();
  const auto r = run("dataset export-cloud " + rawPath() + " --frames 0:5 --voxel 0.2 -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto ply = io::readPly(out);
  ASSERT_TRUE(ply.isOk()) << ply.status().toString();
  auto x = ply->scalarAs<float>("vertex", "x");
  auto z = ply->scalarAs<float>("vertex", "z");
  ASSERT_TRUE(x.isOk());
  ASSERT_TRUE(z.isOk());
  ASSERT_TRUE(ply->scalarAs<float>("vertex", "intensity").isOk());
  // 5 scans of ~115k points on a 0.2 m grid: tens of thousands of voxels, within 70 m + 6 m driven.
  EXPECT_GT(x->size(), 20000u);
  EXPECT_LT(x->size(), 300000u);
  for (std::size_t i = 0; i < x->size(); ++i) {
    ASSERT_LT(std::abs((*x)[i]), 80.0f);
    ASSERT_LT(std::abs((*z)[i]), 40.0f);
  }
  // A finer grid keeps more points.
  const auto fine = (tmp / "fine.ply").string();
  ASSERT_EQ(run("dataset export-cloud " + rawPath() + " --frames 0:5 --voxel 0.1 -o " + fine).exit_code, 0);
  EXPECT_GT(io::readPly(fine)->find("vertex")->count, x->size());
}

TEST(Cli, ErrorsNameTheProblem) {
  const auto missing = run("dataset info /nonexistent/recording");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("/nonexistent/recording"), std::string::npos) << missing.err;

  ARTEMIS_REQUIRE_DATA("kitti_raw");
  const auto range = run("dataset info " + rawPath() + " --frames 10:60");
  EXPECT_EQ(range.exit_code, 1);
  EXPECT_NE(range.err.find("out of bounds"), std::string::npos) << range.err;

  test::TempDir tmp;
  std::ofstream(tmp / "poses.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n";
  const auto poses = run("dataset info " + rawPath() + " --poses " + (tmp / "poses.txt").string());
  EXPECT_EQ(poses.exit_code, 1);
  EXPECT_NE(poses.err.find("1 poses given for a recording of 50 frames"), std::string::npos) << poses.err;
}

TEST(Cli, ReferencePosesReplaceOxts) {
  ARTEMIS_REQUIRE_DATA("kitti_raw/reference_poses.txt");
  const auto r = run("dataset info " + rawPath() + " --json --poses " +
                     (test::dataDir() / "kitti_raw/reference_poses.txt").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto oxts = nlohmann::json::parse(run("dataset info " + rawPath() + " --json").out);
  const auto ref = nlohmann::json::parse(r.out);
  // Same drive, same ~1.2 m steps: path lengths within 5 %, but not identical numbers.
  EXPECT_NEAR(ref["path_length_m"].get<double>(), oxts["path_length_m"].get<double>(),
              0.05 * oxts["path_length_m"].get<double>());
  EXPECT_NE(ref["path_length_m"].get<double>(), oxts["path_length_m"].get<double>());
}

TEST(Cli, PoseRefinementFlagsAreChecked) {
  ARTEMIS_REQUIRE_DATA("kitti_raw");
  test::TempDir tmp;
  const auto off =
      run("run " + rawPath() + " --frames 0:2 --poses none --pose-refinement off --out " + (tmp / "out").string());
  EXPECT_EQ(off.exit_code, 1);
  EXPECT_NE(off.err.find("--poses none needs --pose-refinement on"), std::string::npos) << off.err;
  const auto bad = run("run " + rawPath() + " --frames 0:2 --pose-refinement maybe --out " + (tmp / "out").string());
  EXPECT_NE(bad.exit_code, 0);
  const auto cloud =
      run("dataset export-cloud " + rawPath() + " --frames 0:2 --poses none -o " + (tmp / "cloud.ply").string());
  EXPECT_EQ(cloud.exit_code, 1);
  EXPECT_NE(cloud.err.find("needs poses"), std::string::npos) << cloud.err;
}

TEST(Cli, VehicleBoxIsCheckedAndRecorded) {
  test::TempDir tmp;
  for (const char* bad : {"1,2,3", "2,1,-1,1,-1,0", "a,b,c,d,e,f", "0,1,0,1,0,nan", "lorry"}) {
    const auto r = run(std::string("run --vehicle-box ") + bad + " --out " + (tmp / "bad").string());
    EXPECT_EQ(r.exit_code, 1) << bad;
    EXPECT_NE(r.err.find("--vehicle-box"), std::string::npos) << bad << ": " << r.err;
  }
  ARTEMIS_REQUIRE_DATA("kitti_raw/reference_poses.txt");
  const std::string poses = (test::dataDir() / "kitti_raw/reference_poses.txt").string();
  for (const std::string box : {"kitti", "off", "-4,3,-1.2,1.2,-1.5,0.2"}) {
    const auto out = tmp / ("box_" + std::to_string(box.size()));
    const auto r = run("run " + rawPath() + " --frames 0:2 --poses " + poses + " --pose-refinement off --texture off " +
                       "--vehicle-box " + box + " --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream config_file(out / "config.json");
    const auto config = nlohmann::json::parse(config_file);
    if (box == "off") {
      EXPECT_TRUE(config["vehicle_box_m"].is_null());
    } else {
      ASSERT_EQ(config["vehicle_box_m"].size(), 6u);
      EXPECT_FLOAT_EQ(config["vehicle_box_m"][0].get<float>(), box == "kitti" ? -2.7f : -4.0f);
      EXPECT_FLOAT_EQ(config["vehicle_box_m"][5].get<float>(), box == "kitti" ? 0.0f : 0.2f);
    }
    std::ifstream timing_file(out / "timing.json");
    EXPECT_TRUE(nlohmann::json::parse(timing_file).contains("points_in_vehicle_path"));
  }
}

// artemis run on the drive's first frames refines the OXTS poses by default, and writes what it did.
TEST(Cli, RunRefinesGpsPosesByDefault) {
  ARTEMIS_REQUIRE_DATA("kitti_raw");
  test::TempDir tmp;
  const auto r = run("run " + rawPath() + " --frames 0:5 --out " + (tmp / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("pose refinement: 5 frames registered"), std::string::npos) << r.out;
  std::ifstream config(tmp / "out" / "config.json");
  const auto j = nlohmann::json::parse(config);
  EXPECT_EQ(j["registration"]["pose_refinement"], true);
  EXPECT_TRUE(std::filesystem::exists(tmp / "out" / "registration.json"));
  // The refined trajectory against the OXTS one: they differ, but by centimetres.
  const auto oxts = run("run " + rawPath() + " --frames 0:5 --pose-refinement off --out " + (tmp / "oxts").string());
  ASSERT_EQ(oxts.exit_code, 0) << oxts.err;
  const auto e = run("eval trajectory " + (tmp / "out" / "trajectory.txt").string() + " --ref " +
                     (tmp / "oxts" / "trajectory.txt").string() + " --window 1 4 --json " + (tmp / "t.json").string());
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.out.find("relative pose error"), std::string::npos) << e.out;
  std::ifstream tj(tmp / "t.json");
  const auto t = nlohmann::json::parse(tj);
  ASSERT_EQ(t["relative_pose_error"].size(), 2u);
  EXPECT_EQ(t["relative_pose_error"][1]["window"], 4);
  const double rmse = t["relative_pose_error"][1]["translation_m"]["rmse"].get<double>();
  EXPECT_GT(rmse, 0.005);
  EXPECT_LT(rmse, 0.5);
}

TEST(Cli, EvalTrajectoryErrorsNameTheFile) {
  test::TempDir tmp;
  std::ofstream(tmp / "a.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n";
  std::ofstream(tmp / "b.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n";
  const auto differ = run("eval trajectory " + (tmp / "a.txt").string() + " --ref " + (tmp / "b.txt").string());
  EXPECT_EQ(differ.exit_code, 1);
  EXPECT_NE(differ.err.find("differ in length"), std::string::npos) << differ.err;
  const auto missing = run("eval trajectory " + (tmp / "none.txt").string() + " --ref " + (tmp / "b.txt").string());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("none.txt"), std::string::npos) << missing.err;
  const auto same =
      run("eval trajectory " + (tmp / "a.txt").string() + " --ref " + (tmp / "a.txt").string() + " --window 1");
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_NE(same.out.find("drift: 0.000 m"), std::string::npos) << same.out;
}

}  // namespace
}  // namespace artemis
