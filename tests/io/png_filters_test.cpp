// PNG rows under each of the five filters, read exactly, whichever way the reader takes: the quick
// way (libdeflate and the reader's own unfiltering, for 8-bit images that are not interlaced) or
// libpng's (interlaced files, transparency chunks); and damaged image data, refused as before.

#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "artemis/io/png.hpp"
#include "png_chunks.hpp"
#include "support/test_support.hpp"

namespace artemis::io {
namespace {

int channelsOf(int colour_type) {
  switch (colour_type) {
    case 0: return 1;
    case 4: return 2;
    case 2: return 3;
    default: return 4;
  }
}

unsigned char paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a);
  const int pb = std::abs(p - b);
  const int pc = std::abs(p - c);
  return static_cast<unsigned char>(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

// Row y of `pixels` filtered with filter type y % 5, as a PNG writer would.
std::string filteredRows(const std::vector<unsigned char>& pixels, int width, int height, int channels) {
  const auto row_bytes = static_cast<std::size_t>(width * channels);
  const auto bpp = static_cast<std::size_t>(channels);
  std::string raw;
  for (int y = 0; y < height; ++y) {
    const unsigned char* row = &pixels[static_cast<std::size_t>(y) * row_bytes];
    const unsigned char* prev = y > 0 ? row - row_bytes : nullptr;
    const int type = y % 5;
    raw.push_back(static_cast<char>(type));
    for (std::size_t i = 0; i < row_bytes; ++i) {
      const int left = i >= bpp ? row[i - bpp] : 0;
      const int up = prev != nullptr ? prev[i] : 0;
      const int up_left = i >= bpp && prev != nullptr ? prev[i - bpp] : 0;
      const int predicted = type == 0   ? 0
                            : type == 1 ? left
                            : type == 2 ? up
                            : type == 3 ? (left + up) / 2
                                        : paeth(left, up, up_left);
      raw.push_back(static_cast<char>((row[i] - predicted) & 0xFF));
    }
  }
  return raw;
}

// A PNG file of 8-bit samples; the image data split into IDAT chunks of at most `chunk` bytes,
// after the `before_idat` chunks (type, data).
std::string chunkedPngFile(int width, int height, int colour_type, const std::string& stream, std::size_t chunk,
                           const std::vector<std::pair<std::string, std::string>>& before_idat = {}) {
  std::string file =
      test_png::pngStart(static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), colour_type);
  for (const auto& [type, data] : before_idat) test_png::appendChunk(file, type, data);
  for (std::size_t at = 0; at < stream.size(); at += chunk) {
    test_png::appendChunk(file, "IDAT", stream.substr(at, chunk));
  }
  test_png::appendChunk(file, "IEND", "");
  return file;
}

std::vector<unsigned char> noise(std::size_t n, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<unsigned char> out(n);
  // Smooth with noise on top, so that every predictor has something to predict.
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<unsigned char>((i / 7) * 3 + random() % 23);
  return out;
}

TEST(PngFilters, EveryFilterOfEveryEightBitColourTypeReadsExactly) {
  test::TempDir dir;
  for (const int colour_type : {0, 2, 4, 6}) {
    for (const std::size_t chunk : {std::size_t{1} << 20, std::size_t{97}}) {  // one IDAT, or many
      SCOPED_TRACE(::testing::Message() << "colour type " << colour_type << ", IDAT chunks of " << chunk);
      const int width = 37;
      const int height = 23;
      const int channels = channelsOf(colour_type);
      const auto pixels = noise(static_cast<std::size_t>(width * height * channels), 7u + colour_type);
      const auto path = dir / ("filters" + std::to_string(colour_type) + "_" + std::to_string(chunk) + ".png");
      std::ofstream(path, std::ios::binary) << chunkedPngFile(
          width, height, colour_type, test_png::zlibStream(filteredRows(pixels, width, height, channels)), chunk);
      auto read = readPng8(path);
      ASSERT_TRUE(read.isOk()) << read.status().message();
      EXPECT_EQ(read->width(), width);
      EXPECT_EQ(read->height(), height);
      ASSERT_EQ(read->channels(), channels);
      EXPECT_EQ(read->data(), pixels);
      // Conversions as before: grey to RGB repeats the grey, RGB to grey weighs the channels.
      auto rgb = readPng8(path, 3);
      ASSERT_TRUE(rgb.isOk());
      for (int c = 0; c < 3; ++c) EXPECT_EQ(rgb->at(5, 4, c), read->at(5, 4, channels >= 3 ? c : 0));
    }
  }
}

TEST(PngFilters, TransparencyChunksStillBecomeAlpha) {
  test::TempDir dir;
  // A grey image whose value 7 is transparent: libpng's way, with alpha when asked for it.
  std::vector<unsigned char> pixels(6 * 4, 7);
  pixels[3] = 200;
  std::string trns;
  trns += std::string{'\0', '\x07'};
  std::ofstream(dir / "trns.png", std::ios::binary)
      << chunkedPngFile(6, 4, 0, test_png::zlibStream(filteredRows(pixels, 6, 4, 1)), 1 << 20, {{"tRNS", trns}});
  auto read = readPng8(dir / "trns.png", 2);
  ASSERT_TRUE(read.isOk()) << read.status().message();
  EXPECT_EQ(read->at(0, 0, 0), 7);
  EXPECT_EQ(read->at(0, 0, 1), 0);  // transparent
  EXPECT_EQ(read->at(3, 0, 0), 200);
  EXPECT_EQ(read->at(3, 0, 1), 255);
}

TEST(PngFilters, DamagedImageDataIsRefusedAsBefore) {
  test::TempDir dir;
  const auto pixels = noise(16 * 8 * 3, 3);
  std::string file = chunkedPngFile(16, 8, 2, test_png::zlibStream(filteredRows(pixels, 16, 8, 3)), 1 << 20);
  // A byte of the image data changed: its chunk's CRC no longer matches.
  std::string damaged = file;
  damaged[8 + 25 + 8 + 10] = static_cast<char>(damaged[8 + 25 + 8 + 10] ^ 0x40);
  std::ofstream(dir / "crc.png", std::ios::binary) << damaged;
  auto read = readPng8(dir / "crc.png");
  ASSERT_FALSE(read.isOk());
  EXPECT_NE(read.status().message().find("crc.png: bad PNG"), std::string::npos) << read.status().message();
  // An undefined filter type (5), with the CRC made right.
  std::string raw = filteredRows(pixels, 16, 8, 3);
  raw[3 * (16 * 3 + 1)] = 5;
  std::ofstream(dir / "filter.png", std::ios::binary) << chunkedPngFile(16, 8, 2, test_png::zlibStream(raw), 1 << 20);
  auto bad_filter = readPng8(dir / "filter.png");
  ASSERT_FALSE(bad_filter.isOk());
  EXPECT_NE(bad_filter.status().message().find("filter.png: bad PNG"), std::string::npos)
      << bad_filter.status().message();
}

// A real camera image: the reader's pixels are libpng's own (its simplified API), byte for byte.
TEST(PngFilters, KittiFramesReadAsAnotherDecoderReadsThem) {
  ARTEMIS_REQUIRE_DATA("kitti_raw/2011_09_26/2011_09_26_drive_0013_sync/image_02/data/0000000000.png");
  for (const char* stem : {"0000000000", "0000000024", "0000000049"}) {
    const auto path = test::dataDir() / "kitti_raw/2011_09_26/2011_09_26_drive_0013_sync/image_02/data" /
                      (std::string(stem) + ".png");
    auto read = readPng8(path, 3);
    ASSERT_TRUE(read.isOk()) << read.status().message();
    png_image other{};
    other.version = PNG_IMAGE_VERSION;
    ASSERT_NE(png_image_begin_read_from_file(&other, path.c_str()), 0) << other.message;
    other.format = PNG_FORMAT_RGB;
    std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(other));
    ASSERT_NE(png_image_finish_read(&other, nullptr, pixels.data(), 0, nullptr), 0) << other.message;
    ASSERT_EQ(static_cast<int>(other.width), read->width());
    ASSERT_EQ(static_cast<int>(other.height), read->height());
    EXPECT_EQ(pixels, read->data()) << stem;
  }
}

}  // namespace
}  // namespace artemis::io
