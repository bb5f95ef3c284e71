// Hostile and careless input at the command line: settings outside their range, files that are
// not files, meshes with NaN vertices. Each gets a clear error naming the setting or file, fast.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

using test::RunResult;

struct Setting {
  std::string flag;
  std::string min;
  std::string max;
  std::string below;  // empty: nothing lies below (the range starts at the type's own limit)
  std::string above;
};

// `run` parses its flags before it opens the recording: a value in range gets as far as the
// missing recording, one out of range is refused by name.
RunResult runWith(const std::string& flag, const std::string& value) {
  return test::runCli(fmt::format("run /nonexistent-recording {} {} --out /nonexistent-out", flag, value));
}

void expectAccepted(const std::string& flag, const std::string& value) {
  const RunResult r = runWith(flag, value);
  EXPECT_EQ(r.exit_code, 1) << flag << " " << value;
  EXPECT_NE(r.err.find("/nonexistent-recording"), std::string::npos) << flag << " " << value << ": " << r.err;
}

void expectRefused(const std::string& flag, const std::string& value) {
  const RunResult r = runWith(flag, value);
  EXPECT_NE(r.exit_code, 0) << flag << " " << value;
  EXPECT_NE(r.err.find(flag), std::string::npos) << flag << " " << value << ": " << r.err;
  EXPECT_EQ(r.err.find("/nonexistent-recording"), std::string::npos) << flag << " " << value << ": " << r.err;
}

TEST(Hardening, EveryMapperSettingIsCheckedAtAndBeyondBothEnds) {
  const std::vector<Setting> settings = {
      {"--voxel-size", "0.05", "5", "0.049", "5.1"},
      {"--max-edge", "0.01", "10", "0", "11"},
      {"--remesh-growth", "0.01", "100", "0", "101"},
      {"--first-mesh-points", "3", "1000000", "2", "1000001"},
      {"--rim", "0", "2", "-0.01", "2.1"},
      {"--threads", "0", "1024", "-1", "1025"},
      {"--free-space-range", "1", "500", "0.5", "501"},
      {"--free-space-lookback", "0", "30", "-1", "31"},
      {"--max-vertex-offset", "0", "2", "-1", "3"},
      {"--registration-voxel", "0.05", "10", "0", "11"},
      {"--sigma-photo", "0.0001", "100", "0", "101"},
      {"--min-range", "0", "1000", "-1", "1001"},
      {"--max-range", "0.1", "1000", "0", "1e9"},
      {"--tile-edge", "0.8", "10000", "0.7", "10001"},
      {"--evict-distance", "80.5", "1000000", "80", "1e7"},
      {"--evict-every", "1", "1000000", "0", "1000001"},
  };
  for (const auto& s : settings) {
    SCOPED_TRACE(s.flag);
    expectAccepted(s.flag, s.min);
    expectAccepted(s.flag, s.max);
    expectRefused(s.flag, s.below);
    expectRefused(s.flag, s.above);
  }
  // Not numbers at all: NaN and infinity pass CLI11's own range checks; not these.
  for (const char* flag : {"--voxel-size", "--max-edge", "--rim", "--sigma-depth", "--background-score"}) {
    for (const char* value : {"nan", "inf", "-inf"}) expectRefused(flag, value);
  }
  const RunResult inf = runWith("--voxel-size", "inf");
  EXPECT_NE(inf.err.find("outside the valid range, 0.05 to 5"), std::string::npos) << inf.err;
}

// The other commands' numeric settings: a value beyond either end is refused by name before any
// file is opened (the files here do not exist).
TEST(Hardening, OtherCommandsSettingsAreCheckedBeyondBothEnds) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"sim --out /nonexistent/sim", "--dropout 1"},
      {"sim --out /nonexistent/sim", "--dropout -0.1"},
      {"sim --out /nonexistent/sim", "--azimuth-step 0"},
      {"sim --out /nonexistent/sim", "--range-noise nan"},
      {"sim --out /nonexistent/sim", "--frames 0"},
      {"eval mesh /nonexistent.ply --gt /nonexistent.ply", "--tau 0"},
      {"eval mesh /nonexistent.ply --gt /nonexistent.ply", "--tau inf"},
      {"eval mesh /nonexistent.ply --gt /nonexistent.ply", "--samples-per-m2 0.5"},
      {"render /nonexistent.ply -o /nonexistent.png", "--fov 180"},
      {"render /nonexistent.ply -o /nonexistent.png", "--width 0"},
      {"render /nonexistent.ply -o /nonexistent.png", "--height 16385"},
      {"eval rays /nonexistent", "--max-range 0"},
      {"eval rays /nonexistent", "--tolerance-share 2"},
  };
  for (const auto& [command, setting] : cases) {
    SCOPED_TRACE(command + " " + setting);
    const RunResult r = test::runCli(command + " " + setting);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(setting.substr(0, setting.find(' '))), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("outside the valid range"), std::string::npos) << r.err;
  }
}

TEST(Hardening, ExportCloudVoxelOutsideItsRangeIsRefused) {
  for (const char* voxel : {"1e-5", "0", "nan", "11"}) {
    const RunResult r = test::runCli(std::string("dataset export-cloud /nonexistent --voxel ") + voxel + " -o x.ply");
    EXPECT_NE(r.exit_code, 0) << voxel;
    EXPECT_NE(r.err.find("--voxel"), std::string::npos) << voxel << ": " << r.err;
    EXPECT_NE(r.err.find("0.001 to 10"), std::string::npos) << voxel << ": " << r.err;
  }
}

TEST(Hardening, FilesThatAreNotFilesAreRefusedByName) {
  test::TempDir dir;
  // /dev/zero would be read forever; a folder or a FIFO as a JSON file likewise.
  const RunResult aliases = test::runCli("ground cars --aliases /dev/zero");
  EXPECT_NE(aliases.exit_code, 0);
  EXPECT_NE(aliases.err.find("/dev/zero: is a device, not a regular file"), std::string::npos) << aliases.err;
  const RunResult vocabulary = test::runCli("ground cars --vocabulary " + dir.path().string());
  EXPECT_NE(vocabulary.exit_code, 0);
  EXPECT_NE(vocabulary.err.find("is a folder, not a regular file"), std::string::npos) << vocabulary.err;
  const RunResult mesh = test::runCli("eval mesh /dev/zero --gt /dev/zero");
  EXPECT_NE(mesh.exit_code, 0);
  EXPECT_NE(mesh.err.find("/dev/zero: is a device"), std::string::npos) << mesh.err;
}

// A vertex at NaN or infinity would be scored, drawn and sampled as if it were a place.
TEST(Hardening, MeshesWithNonFiniteVerticesAreRefusedByEveryCommand) {
  test::TempDir dir;
  const std::string mesh = (dir / "nan.ply").string();
  std::ofstream(mesh) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n";
  const std::vector<std::string> commands = {
      "eval mesh " + mesh + " --gt " + mesh,
      "render " + mesh + " --camera 0,0,5,0,0,0 -o " + (dir / "r.png").string(),
      "export " + mesh + " -o " + (dir / "e.glb").string(),
  };
  for (const auto& command : commands) {
    SCOPED_TRACE(command);
    const RunResult r = test::runCli(command);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("nan.ply"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not finite"), std::string::npos) << r.err;
  }
}

TEST(Hardening, MisleadingMessagesSayWhatIsWrong) {
  test::TempDir dir;
  const std::string poses = (dir / "poses.txt").string();
  {
    std::ofstream out(poses);
    for (int i = 0; i < 8; ++i) out << fmt::format("1 0 0 {} 0 1 0 0 0 0 1 0\n", i);
  }
  const RunResult window = test::runCli("eval trajectory " + poses + " --ref " + poses + " --window 0");
  EXPECT_NE(window.exit_code, 0);
  EXPECT_NE(window.err.find("--window"), std::string::npos) << window.err;
  EXPECT_EQ(window.err.find("more than"), std::string::npos) << window.err;
  const RunResult pose = test::runCli("render " + dir.path().string() + " --pose -1 -o " + (dir / "p.png").string());
  EXPECT_NE(pose.exit_code, 0);
  EXPECT_NE(pose.err.find("--pose"), std::string::npos) << pose.err;
  EXPECT_EQ(pose.err.find("give either"), std::string::npos) << pose.err;
}

}  // namespace
}  // namespace artemis
