// artemis sim as a user runs it: the class table, the guard against mixing two runs in one folder,
// reproducing a run from its scene.json, and reading the result with `artemis dataset info`.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(CliSim, WritesASequenceAndPrintsItsClasses) {
  test::TempDir tmp;
  const std::string out = (tmp / "street").string();
  const auto r = test::runCli("sim --preset demo --frames 2 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"car", "person", "building", "vegetation", "trunk", "traffic-sign", "bicycle", "truck"}) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name << " missing from the class table:\n" << r.out;
  }
  EXPECT_NE(r.err.find("settings:"), std::string::npos) << "the effective settings are printed at start";

  const auto info = test::runCli("dataset info " + out + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["format"], "kitti-odometry");
  EXPECT_EQ(j["frames"], 2);
  EXPECT_EQ(j["image_size"][0], 1242);
  EXPECT_GT(j["points_per_frame"]["median"].get<int>(), 100000);

  // A second run into the same folder must not mix with the first.
  const auto again = test::runCli("sim --preset demo --frames 1 --out " + out);
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;

  // scene.json reproduces the run byte for byte.
  const std::string copy = (tmp / "again").string();
  const auto reproduced = test::runCli("sim --params " + out + "/scene.json --out " + copy);
  ASSERT_EQ(reproduced.exit_code, 0) << reproduced.err;
  std::size_t compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(out)) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), out);
    EXPECT_EQ(read(fs::path(copy) / relative), read(entry.path())) << relative;
    ++compared;
  }
  EXPECT_GE(compared, 17u);

  // --force replaces the sequence, leaving no stale frame behind.
  const auto forced = test::runCli("sim --preset demo --frames 1 --force --out " + out);
  ASSERT_EQ(forced.exit_code, 0) << forced.err;
  EXPECT_FALSE(fs::exists(fs::path(out) / "sequences/00/velodyne/000001.bin"));
}

TEST(CliSim, BadSettingsAreClearErrors) {
  test::TempDir tmp;
  const auto frames = test::runCli("sim --frames 0 --out " + (tmp / "a").string());
  EXPECT_NE(frames.exit_code, 0);
  EXPECT_NE(frames.err.find("frames"), std::string::npos) << frames.err;
  std::ofstream(tmp / "bad.json") << R"({"lidar": {"range_noise": 0.1}})";
  const auto params = test::runCli("sim --params " + (tmp / "bad.json").string() + " --out " + (tmp / "b").string());
  EXPECT_NE(params.exit_code, 0);
  EXPECT_NE(params.err.find("bad.json"), std::string::npos) << params.err;
  EXPECT_NE(params.err.find("lidar.range_noise"), std::string::npos) << params.err;
  const auto missing = test::runCli("sim --params " + (tmp / "none.json").string());
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("none.json"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(tmp / "a"));
}

}  // namespace
}  // namespace artemis
