// The malloc settings `artemis run` starts with (core/allocator.hpp), seen from outside: a run's
// frames reuse the memory the frames before them freed, on every thread, rather than having the
// kernel provide (and zero) it page by page again. timing.json counts the page faults.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "cli_run.hpp"
#include "json_file.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

// A sanitizer's allocator replaces malloc: the settings do not apply there (timing.json says
// "system"), so the comparison is made in the other builds only.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)

// The settings with huge pages (where top_pad matters: a heap given back and faulted in again
// costs a 2 MiB page a fault; whether a plain run asks for them depends on the machine, so both
// runs name them), and the same but top_pad: given by the user, they stand alone.
constexpr const char* kTuned =
    "GLIBC_TUNABLES=glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=33554432:"
    "glibc.malloc.trim_threshold=4294967296:glibc.malloc.top_pad=67108864 ";
constexpr const char* kWithoutTopPad =
    "GLIBC_TUNABLES=glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=33554432:"
    "glibc.malloc.trim_threshold=4294967296 ";

std::uint64_t runFaults(const std::string& environment, const fs::path& recording, const fs::path& out) {
  const auto run = test::runCli(environment, "run " + recording.string() + " --out " + out.string());
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const auto timing = test::readJson(out / "timing.json");
  EXPECT_EQ(timing.at("allocator"), "glibc, tuned, huge pages");
  return timing.at("page_faults").get<std::uint64_t>();
}

TEST(AllocatorCli, APlainRunIsTuned) {
  test::TempDir tmp;
  const fs::path street = tmp / "street";
  const auto sim = test::runCli("sim --preset demo --frames 3 --out " + street.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto run = test::runCli("run " + street.string() + " --out " + (tmp / "run").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string allocator = test::readJson(tmp / "run" / "timing.json").at("allocator");
  EXPECT_TRUE(allocator == "glibc, tuned" || allocator == "glibc, tuned, huge pages") << allocator;
}

TEST(AllocatorCli, FramesOnEveryThreadReuseTheMemoryFreedBeforeThem) {
  test::TempDir tmp;
  const fs::path street = tmp / "street";
  const auto sim = test::runCli("sim --preset demo --frames 12 --out " + street.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::uint64_t tuned = runFaults(kTuned, street, tmp / "tuned");
  const std::uint64_t without = runFaults(kWithoutTopPad, street, tmp / "without");
  // Measured: ~3,500 against ~15,000. Without the pad, the reader's and the workers' arenas give
  // their emptied heaps back to the kernel and fault them in again on the next frame.
  EXPECT_LT(2 * tuned, without) << tuned << " page faults tuned, " << without << " without top_pad";
  EXPECT_GT(tuned, 0u);
}

#endif

}  // namespace
}  // namespace artemis
