// populatePages provides the pages of a vector's reserved room, so that writing there later costs
// no page faults, and changes nothing that is already there.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "artemis/core/prefault.hpp"

namespace artemis {
namespace {

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_minflt;
}

// Minor page faults while growing `v` to its capacity.
long faultsFilling(std::vector<std::uint32_t>& v) {
  const long before = minorFaults();
  v.resize(v.capacity(), 1u);
  return minorFaults() - before;
}

TEST(Prefault, TheRoomAheadIsResidentBeforeItIsWrittenAndTheContentsStay) {
  constexpr std::size_t kHeld = 1000;
  constexpr std::size_t kRoom = (std::size_t{64} << 20) / sizeof(std::uint32_t);  // 64 MB: mapped apart
  std::vector<std::uint32_t> v(kHeld);
  std::iota(v.begin(), v.end(), 7u);
  v.reserve(kRoom);
  const ByteRange room = roomAhead(v, v.capacity());
  EXPECT_EQ(room.begin, static_cast<const void*>(v.data() + kHeld));
  EXPECT_EQ(room.bytes, (v.capacity() - kHeld) * sizeof(std::uint32_t));
  EXPECT_EQ(roomAhead(v, 10).bytes, 10 * sizeof(std::uint32_t));

  const bool populated = populatePages(room);
  for (std::size_t i = 0; i < kHeld; ++i) ASSERT_EQ(v[i], 7u + i);  // the page it shares kept its data
  // The same room, not populated, written alike: a fault a page (and, under a sanitizer, its
  // shadow's faults in both).
  std::vector<std::uint32_t> control(kHeld);
  control.reserve(kRoom);
  const long unpopulated = faultsFilling(control);
  const long faults = faultsFilling(v);
  EXPECT_GE(unpopulated, 1000) << "writing 64 MB of fresh memory should fault";
  if (populated) {
    EXPECT_LT(faults * 4, unpopulated) << faults << " faults writing 64 MB that were populated";
  } else {
    EXPECT_GE(faults * 2, unpopulated) << "the kernel did not populate, so the writes should have faulted";
  }
  EXPECT_EQ(v[kHeld - 1], 7u + kHeld - 1);
  EXPECT_EQ(v.back(), 1u);
}

TEST(Prefault, NothingHappensForAnEmptyOrUnmappedRange) {
  EXPECT_FALSE(populatePages({nullptr, 4096}));
  std::vector<int> v;
  EXPECT_FALSE(populatePages(roomAhead(v, 100)));  // no room reserved: zero bytes
  // An address no mapping holds (the first page is never mapped on Linux).
  EXPECT_FALSE(populatePages({reinterpret_cast<const void*>(std::uintptr_t{4096}), 4096}));  // NOLINT
}

}  // namespace
}  // namespace artemis
