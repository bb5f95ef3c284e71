// PNG files that claim more than they hold, or hold more than they claim: refused before any
// pixel memory is allocated, or decoded without inflating what lies past the image.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <string>

#include "artemis/io/png.hpp"
#include "png_chunks.hpp"
#include "support/test_support.hpp"

namespace artemis::io {
namespace {

// A PNG file: signature, IHDR (8-bit, given colour type), one IDAT holding `idat`, IEND.
std::string pngFile(std::uint32_t width, std::uint32_t height, int colour_type, const std::string& idat) {
  std::string file = test_png::pngStart(width, height, colour_type);
  test_png::appendChunk(file, "IDAT", idat);
  test_png::appendChunk(file, "IEND", "");
  return file;
}

// A zlib stream of `megabytes` MiB of zeros in about a thousandth of that: one full-flushed block
// of 1 MiB of zeros (it refers to nothing before it) repeated.
std::string zerosStream(int megabytes) {
  z_stream z{};
  EXPECT_EQ(deflateInit(&z, 9), Z_OK);
  std::string zeros(std::size_t{1} << 20, '\0');
  std::string out;
  std::array<std::string, 2> blocks;
  for (auto& block : blocks) {
    std::string buffer(std::size_t{1} << 16, '\0');
    z.next_in = reinterpret_cast<Bytef*>(zeros.data());
    z.avail_in = static_cast<uInt>(zeros.size());
    z.next_out = reinterpret_cast<Bytef*>(buffer.data());
    z.avail_out = static_cast<uInt>(buffer.size());
    EXPECT_EQ(deflate(&z, Z_FULL_FLUSH), Z_OK);
    EXPECT_EQ(z.avail_in, 0u);
    block.assign(buffer.data(), buffer.size() - z.avail_out);
  }
  deflateEnd(&z);
  out = blocks[0];
  for (int i = 1; i < megabytes; ++i) out += blocks[1];
  return out;  // no final block: the stream never ends, as a bomb need not
}

long peakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

TEST(PngBomb, DataPastTheImageIsNotInflated) {
  test::TempDir dir;
  // 1242 x 375 RGB needs 1.4 MB of raw rows; the stream holds 1 GiB of zeros in about 1 MB.
  const std::string stream = zerosStream(1024);
  ASSERT_LT(stream.size(), std::size_t{2} << 20);
  std::ofstream(dir / "bomb.png", std::ios::binary) << pngFile(1242, 375, 2, stream);
  auto image = readPng8(dir / "bomb.png", 3);
  ASSERT_TRUE(image.isOk()) << image.status().message();
  EXPECT_EQ(image->width(), 1242);
  EXPECT_EQ(image->height(), 375);
  std::size_t nonzero = 0;
  for (const auto v : image->data()) nonzero += v != 0 ? 1 : 0;
  EXPECT_EQ(nonzero, 0u);
  // Inflating the whole stream would have taken a gigabyte.
  EXPECT_LT(peakRssMiB(), 400);
}

TEST(PngBomb, AClaimLargerThanTheFileCanHoldIsRefusedBeforeAllocating) {
  test::TempDir dir;
  const std::string stream = zerosStream(1);
  // 5000 x 5000 RGBA is 100 MB of raw rows; a 1 KB file cannot hold that.
  std::ofstream(dir / "claims.png", std::ios::binary) << pngFile(5000, 5000, 6, stream);
  for (const auto& status : {readPng8(dir / "claims.png").status(), readPng16(dir / "claims.png").status()}) {
    EXPECT_EQ(status.code(), StatusCode::kParseError);
    EXPECT_NE(status.message().find("claims.png"), std::string::npos) << status.message();
  }
  EXPECT_NE(readPng8(dir / "claims.png").status().message().find("more than a file of"), std::string::npos);
  // 60000 x 60000 is over the pixel limit whatever the file holds.
  std::ofstream(dir / "huge.png", std::ios::binary) << pngFile(60000, 60000, 0, stream);
  auto huge = readPng8(dir / "huge.png");
  ASSERT_FALSE(huge.isOk());
  EXPECT_NE(huge.status().message().find("image too large (60000x60000"), std::string::npos) << huge.status().message();
}

TEST(PngBomb, TooLittleDataIsAnErrorNotAPartialImage) {
  test::TempDir dir;
  std::string raw(20 * (1 + 20), '\0');  // 20 x 20 grey needs 420 raw bytes; give it half
  const std::string stream = test_png::zlibStream(raw.substr(0, raw.size() / 2));
  ASSERT_FALSE(stream.empty());
  std::ofstream(dir / "short.png", std::ios::binary) << pngFile(20, 20, 0, stream);
  auto read = readPng8(dir / "short.png");
  ASSERT_FALSE(read.isOk());
  EXPECT_NE(read.status().message().find("short.png: bad PNG"), std::string::npos) << read.status().message();
}

// Inputs the fuzzer found (fuzz/findings/fuzz_png/): a colour profile whose header claims 2 GB
// made libpng allocate that while reading the header. Each is now read within a few megabytes.
TEST(PngBomb, FuzzFindingsAreReadWithoutLargeAllocations) {
  const auto dir = test::sourceDir() / "fuzz" / "findings" / "fuzz_png";
  std::size_t inputs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() == ".txt" || entry.path().filename() == "index.tsv") continue;
    ++inputs;
    (void)readPng8(entry.path(), 3);
    (void)readPng16(entry.path());
  }
  EXPECT_GE(inputs, 3u);
  EXPECT_LT(peakRssMiB(), 400);
}

}  // namespace
}  // namespace artemis::io
