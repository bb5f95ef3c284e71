#include <gtest/gtest.h>

#include "artemis/datasets/dataset.hpp"

namespace artemis::datasets {
namespace {

TEST(FrameRange, ParsesSliceForms) {
  auto r = FrameRange::parse("10:50");
  ASSERT_TRUE(r.isOk());
  EXPECT_EQ(r->begin, 10u);
  EXPECT_EQ(r->end, 50u);
  r = FrameRange::parse("7:");
  ASSERT_TRUE(r.isOk());
  EXPECT_EQ(r->begin, 7u);
  EXPECT_EQ(r->end, FrameRange::kToEnd);
  r = FrameRange::parse(":3");
  ASSERT_TRUE(r.isOk());
  EXPECT_EQ(r->begin, 0u);
  EXPECT_EQ(r->end, 3u);
  r = FrameRange::parse("4");
  ASSERT_TRUE(r.isOk());
  EXPECT_EQ(r->end - r->begin, 1u);
  EXPECT_EQ(FrameRange::parse("10:50")->toString(), "10:50");
}

TEST(FrameRange, RejectsBadText) {
  for (const char* bad : {"", "a:b", "5:5", "9:3", "-1:4", "1:2:3", "1.5:4"}) {
    auto r = FrameRange::parse(bad);
    EXPECT_FALSE(r.isOk()) << bad;
  }
  EXPECT_NE(FrameRange::parse("9:3").status().message().find("empty"), std::string::npos);
  // Found by fuzzing: the largest index made index + 1 wrap to an empty range 2^64-1:0.
  for (const char* huge : {"18446744073709551615", "1000000001", "5:18446744073709551615"}) {
    auto r = FrameRange::parse(huge);
    ASSERT_FALSE(r.isOk()) << huge;
    EXPECT_NE(r.status().message().find("beyond the last frame number"), std::string::npos) << r.status().message();
  }
  EXPECT_TRUE(FrameRange::parse("1000000000").isOk());
}

}  // namespace
}  // namespace artemis::datasets
