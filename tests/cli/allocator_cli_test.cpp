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

// The three settings there were before top_pad: given by the user, they stand alone.
constexpr const char* kWithoutTopPad =
    "GLIBC_TUNABLES=glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=33554432:"
    "glibc.malloc.trim_threshold=4294967296 ";

std::uint64_t runFaults(const std::string& environment, const fs::path& recording, const fs::path& out) {
  const auto run = test::runCli(environment, "run " + recording.string() + " --out " + out.string());
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const auto timing = test::readJson(out / "timing.json");
  EXPECT_EQ(timing.at("allocator"), "glibc, tuned");
  return timing.at("page_faults").get<std::uint64_t>();
}

TEST(AllocatorCli, FramesOnEveryThreadReuseTheMemoryFreedBeforeThem) {
  test::TempDir tmp;
  const fs::path street = tmp / "street";
  const auto sim = test::runCli("sim --preset demo --frames 12 --out " + street.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::uint64_t tuned = runFaults("", street, tmp / "tuned");
  const std::uint64_t without = runFaults(kWithoutTopPad, street, tmp / "without");
  // Measured: ~3,500 against ~15,000. Without the pad, the reader's and the workers' arenas give
  // their emptied heaps back to the kernel and fault them in again on the next frame.
  EXPECT_LT(2 * tuned, without) << tuned << " page faults tuned, " << without << " without top_pad";
  EXPECT_GT(tuned, 0u);
}

#endif

}  // namespace
}  // namespace artemis
