// CLIP's tokenizer against ids worked out by hand from CLIP's construction on a toy vocabulary:
// the 256 byte symbols in CLIP's order (printable ASCII '!'..'~' first, so byte b is id b - 33),
// the same with "</w>" (id + 256), one id per merge (512 + its rank), then the start and end
// tokens. The merges are the toy CLIP's of write_onnx_models.py.
#include "artemis/semantics/clip_tokenizer.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace artemis::semantics {
namespace {

using Ids = std::vector<std::int64_t>;

const char* kMerges =
    "#version: 0.2\n"
    "g r\ngr e\ngre e\ngree n</w>\nr e\nre d</w>\nb l\nbl u\nblu e</w>\nt h\nth i\nthi n\nthin g\nthing s</w>\n";

// A byte's id, for printable ASCII; with the word's end.
std::int64_t ascii(char c) {
  return c - 33;
}
std::int64_t last(char c) {
  return 256 + ascii(c);
}

ClipTokenizer toy() {
  auto t = ClipTokenizer::parse(kMerges, "toy");
  EXPECT_TRUE(t) << t.status().toString();
  return std::move(t).value();
}

TEST(ClipTokenizer, MatchesIdsWorkedOutByHand) {
  const ClipTokenizer t = toy();
  EXPECT_EQ(t.startToken(), 526);
  EXPECT_EQ(t.endToken(), 527);
  EXPECT_EQ(t.vocabularySize(), 528U);
  const std::int64_t red = 512 + 5;      // "re d</w>"
  const std::int64_t green = 512 + 3;    // "gree n</w>"
  const std::int64_t things = 512 + 13;  // "thing s</w>"
  EXPECT_EQ(t.encode("red things"), (Ids{red, things}));
  // Case and white space, as CLIP cleans them.
  EXPECT_EQ(t.encode("  Red \t THINGS\n"), (Ids{red, things}));
  // Punctuation is a word of its own; HTML's entities are undone first.
  EXPECT_EQ(t.encode("red, green!"), (Ids{red, last(','), green, last('!')}));
  EXPECT_EQ(t.encode("red &amp; green"), (Ids{red, last('&'), green}));
  // A word no merge covers stays bytes: b e d.
  EXPECT_EQ(t.encode("bed"), (Ids{ascii('b'), ascii('e'), last('d')}));
  // Contractions split off; digits one by one.
  EXPECT_EQ(t.encode("it's"), (Ids{ascii('i'), last('t'), ascii('\''), last('s')}));
  EXPECT_EQ(t.encode("42"), (Ids{last('4'), last('2')}));
  // A non-ASCII letter's two bytes: 0xC3 is the 128th symbol (106 + 0xC3 - 0xAE), 0xA9 the 103rd.
  EXPECT_EQ(t.encode("\xC3\xA9"), (Ids{106 + (0xC3 - 0xAE), 256 + 94 + (0xA9 - 0xA1)}));
  // Spelled-out special tokens are theirs.
  EXPECT_EQ(t.encode("<|startoftext|>red"), (Ids{526, red}));
  // The model's input: start, ids, end, zeros; cut to the context with the end kept.
  EXPECT_EQ(t.tokens("red things", 6), (Ids{526, red, things, 527, 0, 0}));
  EXPECT_EQ(t.tokens("red things green", 3), (Ids{526, red, 527}));
  EXPECT_EQ(t.tokens("", 4), (Ids{526, 527, 0, 0}));
}

TEST(ClipTokenizer, TakesTheFirstMergesReadsGzipAndRefusesBadLines) {
  // Only the first five merges: "red" is "re" + "d</w>", "green" whole.
  auto first = ClipTokenizer::parse(kMerges, "toy", 5);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->encode("red green"), (Ids{512 + 4, last('d'), 512 + 3}));
  EXPECT_EQ(first->startToken(), 517);
  // The same file gzipped, as OpenAI ships bpe_simple_vocab_16e6.txt.gz.
  test::TempDir tmp;
  const auto gz = tmp / "merges.txt.gz";
  gzFile out = gzopen(gz.c_str(), "wb");
  ASSERT_NE(out, nullptr);
  ASSERT_GT(gzputs(out, kMerges), 0);
  gzclose(out);
  auto zipped = ClipTokenizer::load(gz);
  ASSERT_TRUE(zipped) << zipped.status().toString();
  EXPECT_EQ(zipped->encode("red things"), toy().encode("red things"));
  // A line that is not two symbols names the file and line; a cut gzip is an error.
  auto bad = ClipTokenizer::parse("#version: 0.2\nr e\nre d e\n", "bad.txt");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.status().message().find("bad.txt line 3"), std::string::npos) << bad.status().message();
  std::ifstream in(gz, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(tmp / "cut.gz", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  auto cut = ClipTokenizer::load(tmp / "cut.gz");
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.status().message().find("cut.gz"), std::string::npos) << cut.status().message();
  EXPECT_FALSE(ClipTokenizer::load(tmp / "absent.txt"));
}

}  // namespace
}  // namespace artemis::semantics
