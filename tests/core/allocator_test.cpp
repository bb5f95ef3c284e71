// The glibc malloc tunables a mapping process starts with (core/allocator.hpp): added to what the
// user set, never over it.
#include "artemis/core/allocator.hpp"

#include <gtest/gtest.h>

namespace artemis {
namespace {

TEST(Allocator, TunablesAreAddedToTheUsersAndNeverReplaceThem) {
  const auto fresh = tunedGlibcTunables(nullptr);
  ASSERT_TRUE(fresh.has_value());
  EXPECT_EQ(*fresh,
            "glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=4294967296:"
            "glibc.malloc.top_pad=67108864");
  EXPECT_EQ(tunedGlibcTunables(""), fresh);
  // Other tunables of the user's are kept, ours follow.
  const auto added = tunedGlibcTunables("glibc.pthread.rseq=0");
  ASSERT_TRUE(added.has_value());
  EXPECT_EQ(added->rfind("glibc.pthread.rseq=0:glibc.malloc.hugetlb=1:", 0), 0U) << *added;
  // Any one of ours already set: the user's choice stands, nothing is added.
  EXPECT_FALSE(tunedGlibcTunables("glibc.malloc.hugetlb=0").has_value());
  EXPECT_FALSE(tunedGlibcTunables("glibc.pthread.rseq=0:glibc.malloc.trim_threshold=0").has_value());
  EXPECT_FALSE(tunedGlibcTunables("glibc.malloc.top_pad=0").has_value());
  EXPECT_FALSE(tunedGlibcTunables(fresh->c_str()).has_value());  // a re-executed process stops there
}

}  // namespace
}  // namespace artemis
