// UTF-8 checks against the well-formed sequences of Unicode's table 3-7, byte by byte at its edges.
#include <gtest/gtest.h>

#include <string>

#include "viewer/utf8.hpp"

namespace artemis::viewer {
namespace {

TEST(ViewerUtf8, WellFormedSequencesAreValid) {
  for (const std::string text : {"", "car", "\xC2\x80", "\xDF\xBF", "\xE0\xA0\x80", "\xED\x9F\xBF", "\xEE\x80\x80",
                                 "\xEF\xBF\xBD", "\xF0\x90\x80\x80", "\xF4\x8F\xBF\xBF", "\xC3\xA9t\xC3\xA9"}) {
    EXPECT_TRUE(isValidUtf8(text)) << testing::PrintToString(text);
    EXPECT_EQ(toValidUtf8(text), text);
  }
  EXPECT_TRUE(isValidUtf8(std::string("a\0b", 3)));  // NUL is a character
}

TEST(ViewerUtf8, IllFormedBytesAreInvalid) {
  for (const std::string text :
       {"\xFF", "car\xFF", "\x80", "\xC0\xAF" /* overlong '/' */, "\xC1\xBF", "\xE0\x9F\xBF" /* overlong */,
        "\xED\xA0\x80" /* surrogate */, "\xF0\x8F\xBF\xBF" /* overlong */, "\xF4\x90\x80\x80" /* past U+10FFFF */,
        "\xF5\x80", "\xC3" /* cut short */, "\xE2\x82", "\xC3\x28"}) {
    EXPECT_FALSE(isValidUtf8(text)) << testing::PrintToString(text);
  }
}

TEST(ViewerUtf8, EachIllFormedByteBecomesOneReplacementCharacter) {
  const std::string r = "\xEF\xBF\xBD";
  EXPECT_EQ(toValidUtf8("car\xFF"), "car" + r);
  EXPECT_EQ(toValidUtf8("\xFF\xFE"), r + r);
  EXPECT_EQ(toValidUtf8("\xC3\x28"), r + "(");  // the lead byte alone is dropped
  EXPECT_EQ(toValidUtf8("\xED\xA0\x80x"), r + r + r + "x");
  EXPECT_EQ(toValidUtf8("\xE2\x82"), r + r);
  EXPECT_EQ(toValidUtf8("a\xC3\xA9\xE9"), "a\xC3\xA9" + r);
  EXPECT_TRUE(isValidUtf8(toValidUtf8("\x80\xBF\xC0\xF8\xFF mixed \xE2\x82\xAC \xF0\x9F")));
}

}  // namespace
}  // namespace artemis::viewer
