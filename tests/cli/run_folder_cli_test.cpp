// A run folder holds one run's outputs, never a mixture: a run killed with SIGKILL leaves the
// folder as it was, the next run leaves no staging folder or temporary file behind, and a run
// killed while moving its outputs into place is finished by the next command that reads it.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

using test::hiddenEntries;
using test::slurp;
using test::spawnCli;

class RunFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto sim = test::runCli("sim --preset demo --frames 8 --out " + (dir_ / "sim").string());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  test::RunResult runInto(const std::string& extra) {
    return test::runCli("run " + (dir_ / "sim").string() + " --texture off --out " + out().string() + " " + extra);
  }
  [[nodiscard]] fs::path out() const { return dir_ / "out"; }
  test::TempDir dir_;
};

TEST_F(RunFolder, AKilledRunLeavesTheFolderAsItWasAndTheNextRunCleansUp) {
  ASSERT_EQ(runInto("").exit_code, 0);
  const std::string mesh = slurp(out() / "mesh.ply");
  const std::string config = slurp(out() / "config.json");
  ASSERT_FALSE(mesh.empty());

  const pid_t pid =
      spawnCli({"run", (dir_ / "sim").string(), "--texture", "off", "--voxel-size", "0.3", "--out", out().string()});
  ASSERT_GT(pid, 0);
  // Killed once it has started writing (its configuration is staged first), well before its mesh.
  const fs::path staged_config = out() / (".staging-" + std::to_string(pid)) / "config.json";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(staged_config) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(fs::exists(staged_config));
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it could be killed";

  EXPECT_EQ(slurp(out() / "mesh.ply"), mesh);
  EXPECT_EQ(slurp(out() / "config.json"), config);
  EXPECT_EQ(hiddenEntries(out()).size(), 1u);  // the killed run's staging folder

  ASSERT_EQ(runInto("--voxel-size 0.3").exit_code, 0);
  EXPECT_TRUE(hiddenEntries(out()).empty());
  EXPECT_NE(slurp(out() / "config.json").find("0.3"), std::string::npos);
  EXPECT_NE(slurp(out() / "mesh.ply"), mesh);
}

TEST_F(RunFolder, AMoveStoppedHalfWayIsFinishedByTheNextReader) {
  ASSERT_EQ(runInto("").exit_code, 0);
  // A process that has ended: its pid names the stopped run's staging folder.
  const pid_t dead = test::endedPid();
  const fs::path staging = out() / (".staging-" + std::to_string(dead));
  fs::create_directory(staging);
  // The stopped run wrote a new mesh and configuration and no semantics; its configuration was
  // already moved when it stopped. An earlier run's semantics.json must not stay beside its mesh.
  fs::copy_file(out() / "mesh.ply", staging / "mesh.ply");
  std::ofstream(out() / "semantics.json") << "{}\n";
  std::ofstream(staging / "MANIFEST") << "+config.json\n+mesh.ply\n+trajectory.txt\n-semantics.json\n";
  std::ofstream(out() / (".mesh.ply.tmp-" + std::to_string(dead) + "-0")) << "half a file";

  const auto r = test::runCli("export " + out().string() + " --format obj -o " + (dir_ / "map.obj").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("finishing the move into place"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out() / "semantics.json"));
  EXPECT_TRUE(fs::exists(out() / "mesh.ply"));
  EXPECT_TRUE(hiddenEntries(out()).empty());
}

TEST_F(RunFolder, AKilledSimulationLeavesTheOldSequence) {
  const fs::path velodyne = dir_ / "sim" / "sequences" / "00" / "velodyne";
  const auto scans = [&velodyne] { return std::distance(fs::directory_iterator(velodyne), fs::directory_iterator{}); };
  ASSERT_EQ(scans(), 8);
  const pid_t pid =
      spawnCli({"sim", "--preset", "demo", "--frames", "30", "--force", "--out", (dir_ / "sim").string()});
  ASSERT_GT(pid, 0);
  // Killed once it has written a few frames of the new sequence.
  const fs::path staged = dir_ / "sim" / (".staging-" + std::to_string(pid)) / "sequences" / "00" / "velodyne";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::error_code ec;
  while (std::distance(fs::directory_iterator(staged, ec), fs::directory_iterator{}) < 3 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the simulation ended before it could be killed";
  EXPECT_EQ(scans(), 8);
  const auto r = test::runCli("sim --preset demo --frames 9 --force --out " + (dir_ / "sim").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(scans(), 9);
  EXPECT_TRUE(hiddenEntries(dir_ / "sim").empty());
}

}  // namespace
}  // namespace artemis
