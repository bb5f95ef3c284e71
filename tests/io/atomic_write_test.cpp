// Whole-file writes: the target is replaced whole, and the temporary files that killed writers left
// beside a target are removed by its next write, never those of a writer still running.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <span>
#include <string>

#include "artemis/io/file.hpp"
#include "support/ended_process.hpp"
#include "support/test_support.hpp"

namespace artemis::io {
namespace {

namespace fs = std::filesystem;

Status writeText(const fs::path& path, const std::string& text) {
  return writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

TEST(AtomicWrite, TemporaryFileNamesSayTheirWriter) {
  EXPECT_EQ(temporaryFileOwner(".mesh.ply.tmp-1234-0"), 1234);
  EXPECT_EQ(temporaryFileOwner(".a.tmp-b.tmp-77-3"), 77);
  EXPECT_FALSE(temporaryFileOwner("mesh.ply.tmp-1234-0"));  // not hidden: a user's file
  EXPECT_FALSE(temporaryFileOwner(".mesh.ply.tmp-1234"));   // no counter
  EXPECT_FALSE(temporaryFileOwner(".mesh.ply.tmp--1-0"));
  EXPECT_FALSE(temporaryFileOwner(".mesh.ply"));
  EXPECT_TRUE(processRunning(::getpid()));
  EXPECT_FALSE(processRunning(test::endedPid()));
  EXPECT_FALSE(processRunning(0));
  EXPECT_FALSE(processRunning(-5));
}

TEST(AtomicWrite, ANewWriteRemovesWhatStoppedWritersOfTheSameFileLeft) {
  test::TempDir dir;
  const std::string dead = std::to_string(test::endedPid());
  const std::string alive = std::to_string(::getpid());
  for (const std::string& name :
       {".map.glb.tmp-" + dead + "-0", ".map.glb.tmp-" + dead + "-12", ".map.glb.tmp-" + alive + "-99",
        ".other.glb.tmp-" + dead + "-0", "map.glb.tmp-" + dead + "-0"}) {
    std::ofstream(dir / name) << "half a file";
  }
  ASSERT_TRUE(writeText(dir / "map.glb", "whole").isOk());
  EXPECT_FALSE(fs::exists(dir / (".map.glb.tmp-" + dead + "-0")));
  EXPECT_FALSE(fs::exists(dir / (".map.glb.tmp-" + dead + "-12")));
  EXPECT_TRUE(fs::exists(dir / (".map.glb.tmp-" + alive + "-99")));  // a writer still running
  EXPECT_TRUE(fs::exists(dir / (".other.glb.tmp-" + dead + "-0")));  // another file's
  EXPECT_TRUE(fs::exists(dir / ("map.glb.tmp-" + dead + "-0")));     // not a temporary name
  std::ifstream in(dir / "map.glb");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "whole");
  EXPECT_EQ(removeStaleTemporaries(dir / "map.glb"), 0);
}

}  // namespace
}  // namespace artemis::io
