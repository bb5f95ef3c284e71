// Bad PLY input: each case must fail with a message naming the file and the problem, and no
// input at all (truncated or corrupted anywhere) may crash or read out of bounds.

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>

#include "artemis/io/ply.hpp"
#include "support/test_support.hpp"

namespace artemis::io {
namespace {

class PlyErrors : public ::testing::Test {
 protected:
  // Writes `bytes` as `name` and reads it back, expecting failure.
  Status readBad(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    auto read = readPly(dir_ / name);
    EXPECT_FALSE(read.isOk()) << name << " was accepted";
    if (read.isOk()) return Status::ok();
    EXPECT_NE(read.status().message().find(name), std::string::npos) << read.status().message();
    return read.status();
  }

  static void expectMentions(const Status& status, const std::string& text) {
    EXPECT_NE(status.message().find(text), std::string::npos) << "'" << text << "' not in: " << status.message();
  }

  test::TempDir dir_;
};

std::string floatBytes(std::size_t count) {
  return std::string(count * sizeof(float), '\x01');
}

TEST_F(PlyErrors, MissingFile) {
  auto read = readPly(dir_ / "absent.ply");
  ASSERT_FALSE(read.isOk());
  EXPECT_EQ(read.status().code(), StatusCode::kNotFound);
  expectMentions(read.status(), "absent.ply");
}

TEST_F(PlyErrors, NotAPlyFile) {
  const Status status = readBad("picture.ply", "\x89PNG\r\n\x1a\nrest of a png");
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  expectMentions(status, "not a PLY file");
  expectMentions(readBad("empty.ply", ""), "not a PLY file");
}

TEST_F(PlyErrors, BadHeaderKeyword) {
  const Status status = readBad("mesh.ply", "ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n");
  expectMentions(status, "mesh.ply line 3: unknown header keyword 'elemnt'");
}

// Found by fuzzing: a carriage return inside a name or comment was read, and then could not be
// written back.
TEST_F(PlyErrors, ControlCharactersInTheHeaderAreRefused) {
  const std::string tail = "element vertex 0\nproperty float x\nend_header\n";
  expectMentions(readBad("cr_comment.ply", "ply\nformat ascii 1.0\ncomment a\rb\n" + tail),
                 "line 3: control character 0x0D in the header");
  expectMentions(readBad("cr_name.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\ry\nend_header\n"),
                 "line 4: control character 0x0D");
  expectMentions(readBad("nul.ply", std::string("ply\nformat ascii 1.0\ncomment ") + '\0' + "\n" + tail), "0x00");
}

TEST_F(PlyErrors, UnknownPropertyType) {
  const Status status =
      readBad("mesh.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty flaot y\nend_header\n");
  expectMentions(status, "mesh.ply line 5: unknown property type 'flaot'");
}

TEST_F(PlyErrors, OtherHeaderProblems) {
  expectMentions(readBad("fmt.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"),
                 "line 2: unknown format 'binary_middle_endian'");
  expectMentions(readBad("count.ply", "ply\nformat ascii 1.0\nelement vertex many\nend_header\n"),
                 "line 3: bad element count 'many'");
  expectMentions(readBad("orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n"),
                 "line 3: property before any element");
  expectMentions(readBad("listf.ply", "ply\nformat ascii 1.0\nelement f 1\nproperty list float int v\nend_header\n"),
                 "line 4: list count type 'float' is not an integer type");
  expectMentions(readBad("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"), "no end_header");
  expectMentions(readBad("nofmt.ply", "ply\nelement vertex 0\nend_header\n"), "before any format line");
}

TEST_F(PlyErrors, TruncatedBinary) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  const Status status = readBad("cloud.ply", header + floatBytes(200));
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  expectMentions(status, "cloud.ply: truncated: expected 1200 bytes of vertex data, found 800");
}

TEST_F(PlyErrors, HugeDeclaredCountIsRejectedBeforeAllocating) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty double x\n"
      "property double y\nend_header\n";
  expectMentions(readBad("huge.ply", header + floatBytes(4)), "truncated: expected 18446744073709551615 x 16 bytes");
  const std::string list_header =
      "ply\nformat binary_little_endian 1.0\nelement face 4000000000000\nproperty list uchar int v\nend_header\n";
  expectMentions(readBad("hugefaces.ply", list_header + "\x03"), "expected at least 4000000000000 bytes of face data");
  const std::string ascii_header =
      "ply\nformat ascii 1.0\nelement vertex 4000000000000\nproperty float x\nend_header\n";
  expectMentions(readBad("hugeascii.ply", ascii_header + "1\n2\n"), "expected 4000000000000 vertex lines, found 2");
}

TEST_F(PlyErrors, ListCountExceedsData) {
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
  bytes += std::string("\x03\0\0\0\0\1\0\0\0\2\0\0\0", 13);  // a good triangle
  bytes += std::string("\xFF\0\0\0\0\1\0\0\0", 9);           // 255 indices announced, 2 present
  const Status status = readBad("faces.ply", bytes);
  expectMentions(status, "faces.ply: truncated: face 1 property 'vertex_indices' needs 1020 bytes, 8 left");

  const std::string ascii =
      "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n4 0 1 2\n";
  expectMentions(readBad("faces_ascii.ply", ascii), "faces_ascii.ply line 6: face 0: too few values");
  const std::string negative =
      "ply\nformat ascii 1.0\nelement face 1\nproperty list char int vertex_indices\nend_header\n-1 0\n";
  expectMentions(readBad("negative.ply", negative), "line 6: face 0: negative list length");
}

TEST_F(PlyErrors, AsciiCountMismatch) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nend_header\n";
  expectMentions(readBad("short.ply", header + "1 2\n3 4\n5 6\n"),
                 "short.ply: truncated: expected 5 vertex lines, found 3");
  const std::string fewer = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n";
  expectMentions(readBad("long.ply", fewer + "1\n2\n3\n"), "long.ply line 8: data after the last element");
  expectMentions(readBad("wide.ply", fewer + "1\n2 3\n"),
                 "wide.ply line 7: vertex 1: more values than its 1 properties");
  expectMentions(readBad("narrow.ply", header + "1 2\n3\n"),
                 "narrow.ply line 8: vertex 1: too few values (missing 'y')");
}

TEST_F(PlyErrors, AsciiBadValues) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty uchar red\nend_header\n";
  expectMentions(readBad("text.ply", header + "1 2 3\n4 abc 5\n"),
                 "text.ply line 9: vertex 1: bad float value 'abc' for property 'y'");
  expectMentions(readBad("range.ply", header + "1 2 256\n"),
                 "line 8: vertex 0: bad uchar value '256' for property 'red'");
  expectMentions(readBad("partial.ply", header + "1 2x 3\n"), "bad float value '2x'");
  expectMentions(readBad("float_int.ply", header + "1 2 3.5\n"), "bad uchar value '3.5'");
}

// Every prefix of a valid file, and many corrupted copies, must be handled without a crash
// (run under ASan/UBSan to catch reads out of bounds); every strict prefix must be an error.
TEST_F(PlyErrors, TruncationsAndCorruptionsNeverCrash) {
  for (const PlyFormat format : {PlyFormat::kBinaryLittleEndian, PlyFormat::kAscii}) {
    PlyData data;
    data.format = format;
    ASSERT_TRUE(data.setScalar<float>("vertex", "x", {1.5F, -2.F, 3.25F}).isOk());
    ASSERT_TRUE(data.setScalar<std::uint16_t>("vertex", "id", {1, 2, 60000}).isOk());
    ASSERT_TRUE(data.setList<std::int32_t>("face", "vertex_indices", PlyType::kUInt8, {{0, 1, 2}, {2, 1, 0}}).isOk());
    const auto good = dir_ / "good.ply";
    ASSERT_TRUE(writePly(good, data).isOk());
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_TRUE(readPly(good).isOk());

    const auto cut = dir_ / "cut.ply";
    // ASCII files may lose their final newline and stay valid; binary ones may not lose anything.
    const std::size_t must_fail_below = format == PlyFormat::kAscii ? bytes.size() - 1 : bytes.size();
    for (std::size_t size = 0; size < bytes.size(); ++size) {
      std::ofstream(cut, std::ios::binary | std::ios::trunc) << bytes.substr(0, size);
      auto read = readPly(cut);
      if (size < must_fail_below) {
        EXPECT_FALSE(read.isOk()) << "prefix of " << size << " bytes accepted";
        if (!read.isOk()) {
          EXPECT_NE(read.status().message().find("cut.ply"), std::string::npos);
        }
      }
    }
    std::mt19937 random(12345);
    for (int trial = 0; trial < 500; ++trial) {
      std::string corrupt = bytes;
      const int changes = 1 + trial % 4;
      for (int c = 0; c < changes; ++c) {
        corrupt[random() % corrupt.size()] = static_cast<char>(random() % 256);
      }
      std::ofstream(cut, std::ios::binary | std::ios::trunc) << corrupt;
      (void)readPly(cut);  // any outcome but a crash is fine
    }
  }
}

}  // namespace
}  // namespace artemis::io
