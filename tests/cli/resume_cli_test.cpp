// A run (of a drive there and back, whose tiles leave memory and come back) that is killed
// (SIGKILL, at a moment drawn at random) or stopped (SIGINT) goes on with
// `artemis run --resume OUT` from its last checkpoint and ends with the same files, byte for byte,
// as a run that was never stopped; checkpoints that are damaged, of another format or of other
// settings are refused with a message saying which.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.hpp"
#include "json_file.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

// The files of a finished run that must not depend on whether it was stopped (timing.json and
// registration.json hold times).
const std::vector<std::string> kSameFiles = {"mesh.ply", "mesh_classes.ply", "trajectory.txt", "semantics.json",
                                             "config.json"};

// What timing.json names as the allocator of a run started plainly: the tuned glibc malloc,
// except in sanitizer builds, whose allocator replaces malloc.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr const char* kTunedAllocator = "system";
#else
constexpr const char* kTunedAllocator = "glibc, tuned";
#endif

// Frames of the street (driven there and back: twice as many, less one). The kill test needs the
// run to last beyond its first checkpoint by up to 0.6 s; it runs in the Release pass only, and
// the sanitizer pass maps a shorter street, too short for a tile to leave and come back.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr int kFrames = 8;
constexpr bool kTilesComeBack = false;
#else
constexpr int kFrames = 14;
constexpr bool kTilesComeBack = true;
#endif

// Tiles leave memory early (15 m behind the drive, texturing within 12 m), so that the checkpoint
// holds a map of which some tiles are already written, and mesh.ply is stitched from tile files.
const std::vector<std::string> kTileFlags = {"--evict-distance", "15",  "--texture-range", "12",
                                             "--tile-edge",      "6.4", "--evict-every",   "3"};

std::string joined(const std::vector<std::string>& args) {
  std::string s;
  for (const std::string& a : args) s += " " + a;
  return s;
}

// A short simulated street with moving traffic, and its uninterrupted run (with semantics, texture,
// free space, tiles: every stage that carries state from frame to frame).
class CliResume : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    tmp_ = new test::TempDir();
    const fs::path there = *tmp_ / "there";
    const auto sim = test::runCli("sim --preset demo --frames " + std::to_string(kFrames) +
                                  " --azimuth-step 0.36 --traffic street --out " + there.string());
    if (sim.exit_code != 0) {
      setup_error_ = "artemis sim failed: " + sim.err;
      return;
    }
    // Driven there and back: the tiles finished on the way are loaded back on the way home.
    std::string why;
    if (!test::writeThereAndBack(there, street(), kFrames, &why)) {
      setup_error_ = why;
      return;
    }
    const auto run = test::runCli("run " + street().string() + " --out " + (*tmp_ / "whole").string() +
                                  " --checkpoint-every 0 --query cars --segmenter sim" + joined(kTileFlags));
    if (run.exit_code != 0) setup_error_ = "artemis run failed: " + run.err;
  }
  void SetUp() override { ASSERT_TRUE(setup_error_.empty()) << setup_error_; }
  static void TearDownTestSuite() {
    delete tmp_;
    tmp_ = nullptr;
  }
  static fs::path street() { return *tmp_ / "street"; }
  static fs::path whole() { return *tmp_ / "whole"; }

  // Starts the run into `out`, checkpointing every 2 frames, and waits for its first checkpoint.
  static pid_t startRun(const fs::path& out) {
    std::vector<std::string> args{"run", street().string(), "--out", out.string(),  "--checkpoint-every",
                                  "2",   "--query",         "cars",  "--segmenter", "sim"};
    args.insert(args.end(), kTileFlags.begin(), kTileFlags.end());
    const pid_t pid = test::spawnCli(args);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (!fs::exists(out / "checkpoint.bin") && std::chrono::steady_clock::now() < give_up) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return pid;
  }

  static void expectSameAsWhole(const fs::path& out) {
    for (const std::string& name : kSameFiles) {
      ASSERT_TRUE(fs::exists(out / name)) << name;
      EXPECT_TRUE(test::slurp(out / name) == test::slurp(whole() / name)) << name << " differs";
    }
    // The map went to tile files as the drive went on, and came back from them.
    const auto tiles = test::readJson(out / "timing.json")["tiles"];
    EXPECT_GT(tiles["finished_during_run"].get<int>(), 0) << tiles;
    if (kTilesComeBack) {
      EXPECT_GT(tiles["reloaded"].get<int>(), 0) << tiles;
    }
    EXPECT_TRUE(fs::is_directory(out / "tiles"));
    // The finished run leaves no checkpoint, staging folder, running tile folder or temporary file
    // behind.
    EXPECT_FALSE(fs::exists(out / "checkpoint.bin"));
    EXPECT_FALSE(fs::exists(out / "checkpoint.json"));
    EXPECT_TRUE(test::hiddenEntries(out).empty());
  }

  static test::TempDir* tmp_;
  static std::string setup_error_;
};

test::TempDir* CliResume::tmp_ = nullptr;
std::string CliResume::setup_error_;

TEST_F(CliResume, KilledAtARandomMomentItResumesToTheSameFiles) {
  const fs::path out = *tmp_ / "killed";
  // Up to 0.6 s after the first checkpoint: somewhere in the frames after it, in a frame or while
  // the next checkpoint is written. The draw is in the log, to replay a failure.
  const unsigned seed = std::random_device{}();
  const int delay_ms = static_cast<int>(std::mt19937(seed)() % 600);
  SCOPED_TRACE("killed " + std::to_string(delay_ms) + " ms after the first checkpoint (seed " + std::to_string(seed) +
               ")");
  const pid_t pid = startRun(out);
  ASSERT_TRUE(fs::exists(out / "checkpoint.bin")) << "no checkpoint appeared";
  std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
  ::kill(pid, SIGKILL);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";

  const auto resumed = test::runCli("run --resume " + out.string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("resumed from"), std::string::npos) << resumed.err;
  expectSameAsWhole(out);
  const auto timing = test::readJson(out / "timing.json");
  EXPECT_GT(timing["checkpoints"]["resumed_at_frame"].get<int>(), 0);
  EXPECT_EQ(timing["frames"].get<int>(), 2 * kFrames - 1);  // there and back
}

TEST_F(CliResume, StoppedWithCtrlCItRefusesForeignCheckpointsAndResumes) {
  const fs::path out = *tmp_ / "stopped";
  const pid_t pid = startRun(out);
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);  // stopped, as after Ctrl-C
  ASSERT_TRUE(fs::exists(out / "checkpoint.bin"));

  // Copies of the folder with one thing wrong each.
  const auto variant = [&](const std::string& name, auto&& spoil) {
    const fs::path dir = *tmp_ / name;
    fs::copy(out, dir, fs::copy_options::recursive);
    spoil(dir);
    return test::runCli("run --resume " + dir.string());
  };
  const auto patch = [](const fs::path& file, std::streamoff at, char byte) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(at);
    f.put(byte);
  };
  const auto damaged = variant("damaged", [&](const fs::path& dir) {
    patch(dir / "checkpoint.bin", static_cast<std::streamoff>(fs::file_size(dir / "checkpoint.bin") / 2), '\x5a');
  });
  EXPECT_EQ(damaged.exit_code, 1);
  EXPECT_NE(damaged.err.find("damaged"), std::string::npos) << damaged.err;
  // The format number follows the 8-byte length and 18 characters of "ARTEMIS checkpoint".
  const auto future = variant("future", [&](const fs::path& dir) { patch(dir / "checkpoint.bin", 26, '\x63'); });
  EXPECT_EQ(future.exit_code, 1);
  EXPECT_NE(future.err.find("format 99"), std::string::npos) << future.err;
  const auto other = variant("other", [&](const fs::path& dir) {
    auto record = test::readJson(dir / "checkpoint.json");
    record["args"].insert(record["args"].begin(), {"--voxel-size", "0.5"});
    std::ofstream(dir / "checkpoint.json") << record.dump();
  });
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("other settings"), std::string::npos) << other.err;
  const auto extra = test::runCli("run --resume " + out.string() + " --voxel-size 0.5");
  EXPECT_EQ(extra.exit_code, 1);
  EXPECT_NE(extra.err.find("--resume takes no other flags"), std::string::npos) << extra.err;
  const auto nothing = test::runCli("run --resume " + (*tmp_ / "nowhere").string());
  EXPECT_EQ(nothing.exit_code, 1);
  EXPECT_NE(nothing.err.find("holds no run that can be resumed"), std::string::npos) << nothing.err;

  // Resumed with glibc's default allocator settings (core/allocator.hpp): the same files, as
  // the allocator changes no result; timing.json says which ran.
  ::setenv("ARTEMIS_ALLOCATOR", "system", 1);
  const auto resumed = test::runCli("run --resume " + out.string());
  ::unsetenv("ARTEMIS_ALLOCATOR");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expectSameAsWhole(out);
  EXPECT_EQ(test::readJson(out / "timing.json")["allocator"], "system");
  // (With huge pages or not, by the machine: core/allocator.hpp.)
  const std::string tuned = test::readJson(whole() / "timing.json")["allocator"];
  EXPECT_EQ(tuned.rfind(kTunedAllocator, 0), 0u) << tuned;
}

}  // namespace
}  // namespace artemis
