// The glibc malloc tunables a mapping process starts with (core/allocator.hpp): added to what the
// user set, never over it; huge pages only where asked for.
#include "artemis/core/allocator.hpp"

#include <gtest/gtest.h>

namespace artemis {
namespace {

TEST(Allocator, TunablesAreAddedToTheUsersAndNeverReplaceThem) {
  const auto fresh = tunedGlibcTunables(nullptr, false);
  ASSERT_TRUE(fresh.has_value());
  EXPECT_EQ(
      *fresh,
      "glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=4294967296:glibc.malloc.top_pad=67108864");
  EXPECT_EQ(tunedGlibcTunables("", false), fresh);
  const auto huge = tunedGlibcTunables(nullptr, true);
  ASSERT_TRUE(huge.has_value());
  EXPECT_EQ(*huge, "glibc.malloc.hugetlb=1:" + *fresh);
  // Other tunables of the user's are kept, ours follow.
  const auto added = tunedGlibcTunables("glibc.pthread.rseq=0", true);
  ASSERT_TRUE(added.has_value());
  EXPECT_EQ(added->rfind("glibc.pthread.rseq=0:glibc.malloc.hugetlb=1:", 0), 0U) << *added;
  // Any one of ours already set: the user's choice stands, nothing is added.
  EXPECT_FALSE(tunedGlibcTunables("glibc.malloc.hugetlb=0", false).has_value());
  EXPECT_FALSE(tunedGlibcTunables("glibc.pthread.rseq=0:glibc.malloc.trim_threshold=0", true).has_value());
  EXPECT_FALSE(tunedGlibcTunables("glibc.malloc.top_pad=0", false).has_value());
  // A re-executed process stops there, with or without huge pages.
  EXPECT_FALSE(tunedGlibcTunables(fresh->c_str(), true).has_value());
  EXPECT_FALSE(tunedGlibcTunables(huge->c_str(), false).has_value());
}

TEST(Allocator, APageFaultIsMeasured) {
  // A fresh page costs something to provide, and less than a millisecond on any machine worth
  // mapping on (1.6 us on a 2-core virtual machine, 15 us on another).
  const double us = pageFaultMicros();
  EXPECT_GT(us, 0.0);
  EXPECT_LT(us, 1000.0);
}

}  // namespace
}  // namespace artemis
