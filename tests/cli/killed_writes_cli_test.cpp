// Commands that write one file (export, eval … --json) never leave half of it: a command killed with
// SIGKILL while writing leaves the file as it was, and the next write of the same file removes the
// temporary file the killed one left.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

// A flat grid of n x n vertices 0.1 m apart as a binary PLY: large enough (n = 700: 1M faces,
// 19 MB) that writing its export takes a while.
void writeGridPly(const fs::path& path, int n) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << n * n
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << 2 * (n - 1) * (n - 1)
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const float xyz[3] = {0.1f * static_cast<float>(c), 0.1f * static_cast<float>(r), 0.0f};
      out.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
    }
  }
  const auto face = [&out](std::int32_t a, std::int32_t b, std::int32_t c) {
    const std::uint8_t three = 3;
    const std::int32_t ids[3] = {a, b, c};
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(ids), sizeof(ids));
  };
  for (int r = 0; r + 1 < n; ++r) {
    for (int c = 0; c + 1 < n; ++c) {
      const std::int32_t v = r * n + c;
      face(v, v + 1, v + n + 1);
      face(v, v + n + 1, v + n);
    }
  }
}

bool hasEntryStartingWith(const fs::path& folder, const std::string& prefix) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (entry.path().filename().string().rfind(prefix, 0) == 0) return true;
  }
  return false;
}

// Waits for `pid`; true when a signal ended it.
bool endedBySignal(pid_t pid) {
  int status = 0;
  return ::waitpid(pid, &status, 0) == pid && WIFSIGNALED(status);
}

class KilledWrites : public ::testing::Test {
 protected:
  void SetUp() override {
    writeGridPly(big(), 700);
    writeGridPly(small(), 50);
    fs::create_directory(out());
  }
  [[nodiscard]] fs::path big() const { return dir_ / "big.ply"; }
  [[nodiscard]] fs::path small() const { return dir_ / "small.ply"; }
  [[nodiscard]] fs::path out() const { return dir_ / "out"; }
  test::TempDir dir_;
};

TEST_F(KilledWrites, AnExportKilledWhileWritingLeavesTheOldFileAndTheNextCleansUp) {
  const fs::path glb = out() / "map.glb";
  auto r = test::runCli("export " + small().string() + " --format glb -o " + glb.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string old = test::slurp(glb);
  ASSERT_FALSE(old.empty());

  // Killed as soon as its temporary file appears; a few tries, since the write may also finish
  // between the look and the kill.
  bool killed_while_writing = false;
  for (int attempt = 0; attempt < 5 && !killed_while_writing; ++attempt) {
    const pid_t pid = test::spawnCli({"export", big().string(), "--format", "glb", "-o", glb.string()});
    ASSERT_GT(pid, 0);
    // Polled without sleeping (the temporary file lives for milliseconds); a child that ended
    // before it was seen ends this try.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    int status = 0;
    bool exited = false;
    while (!hasEntryStartingWith(out(), ".map.glb.tmp-") && std::chrono::steady_clock::now() < deadline) {
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
    }
    if (!exited) {
      ::kill(pid, SIGKILL);
      killed_while_writing = endedBySignal(pid) && hasEntryStartingWith(out(), ".map.glb.tmp-");
    }
    if (!killed_while_writing) {
      // It finished: start again from the small export.
      ASSERT_EQ(test::runCli("export " + small().string() + " --format glb -o " + glb.string()).exit_code, 0);
    }
  }
  ASSERT_TRUE(killed_while_writing) << "no export could be killed while it wrote";
  EXPECT_EQ(test::slurp(glb), old);

  r = test::runCli("export " + small().string() + " --format glb -o " + glb.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::hiddenEntries(out()).empty());
  EXPECT_EQ(test::slurp(glb), old);
}

TEST_F(KilledWrites, AnEvaluationKilledBeforeItsJsonLeavesTheOldScoresAndTheNextCleansUp) {
  const fs::path json = out() / "scores.json";
  const std::string eval = "eval mesh " + small().string() + " --gt " + small().string() + " --json " + json.string();
  auto r = test::runCli(eval);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string old = test::slurp(json);
  ASSERT_TRUE(nlohmann::json::accept(old));

  const pid_t pid = test::spawnCli({"eval", "mesh", big().string(), "--gt", big().string(), "--json", json.string()});
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ::kill(pid, SIGKILL);
  ASSERT_TRUE(endedBySignal(pid)) << "the evaluation ended before it could be killed";
  EXPECT_EQ(test::slurp(json), old);

  // A write killed half-way by an earlier process: the next evaluation removes its leftover.
  std::ofstream(out() / (".scores.json.tmp-" + std::to_string(test::endedPid()) + "-0")) << "{\"half\":";
  r = test::runCli(eval);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::hiddenEntries(out()).empty());
  EXPECT_TRUE(nlohmann::json::accept(test::slurp(json)));
}

TEST_F(KilledWrites, ATemporaryFileOfARunningWriterIsLeftAlone) {
  // This test's own process is running: a temporary file in its name belongs to a live writer.
  const fs::path live = out() / (".map.glb.tmp-" + std::to_string(::getpid()) + "-7");
  std::ofstream(live) << "being written";
  const auto r = test::runCli("export " + small().string() + " --format glb -o " + (out() / "map.glb").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(live));
}

}  // namespace
}  // namespace artemis
