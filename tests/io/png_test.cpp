// PNG round trips with exact pixel values, conversions, and bad input.

#include "artemis/io/png.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "support/test_support.hpp"

namespace artemis::io {
namespace {

ImageU8 pattern8(int width, int height, int channels) {
  ImageU8 image(width, height, channels);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      for (int c = 0; c < channels; ++c)
        image.at(u, v, c) = static_cast<std::uint8_t>((u * 37 + v * 11 + c * 101) % 256);
    }
  }
  return image;
}

void expectSamePixels(const ImageU8& a, const ImageU8& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  ASSERT_EQ(a.channels(), b.channels());
  EXPECT_EQ(a.data(), b.data());
}

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Png, EightBitRoundTripsEveryChannelCount) {
  test::TempDir dir;
  for (int channels = 1; channels <= 4; ++channels) {
    SCOPED_TRACE(channels);
    const ImageU8 image = pattern8(31, 17, channels);
    const auto path = dir / ("image" + std::to_string(channels) + ".png");
    ASSERT_TRUE(writePng(path, image).isOk());
    auto read = readPng8(path);
    ASSERT_TRUE(read.isOk()) << read.status().toString();
    expectSamePixels(image, *read);
    EXPECT_EQ(read->at(30, 16, channels - 1),
              static_cast<std::uint8_t>((30 * 37 + 16 * 11 + (channels - 1) * 101) % 256));
  }
}

TEST(Png, RgbValuesExact) {
  test::TempDir dir;
  ImageU8 image(2, 2, 3);
  const std::uint8_t values[] = {0, 1, 2, 127, 128, 129, 253, 254, 255, 10, 200, 77};
  std::copy(std::begin(values), std::end(values), image.data().begin());
  ASSERT_TRUE(writePng(dir / "rgb.png", image).isOk());
  auto read = readPng8(dir / "rgb.png", 3);
  ASSERT_TRUE(read.isOk());
  EXPECT_EQ(read->channels(), 3);
  EXPECT_EQ(read->at(0, 1, 2), 255);
  EXPECT_EQ(read->at(1, 0, 2), 129);
  EXPECT_EQ(read->at(1, 1, 1), 200);
  expectSamePixels(image, *read);
}

TEST(Png, ConvertsChannelsOnRequest) {
  test::TempDir dir;
  ImageU8 grey(3, 1, 1);
  grey.data() = {0, 100, 255};
  ASSERT_TRUE(writePng(dir / "grey.png", grey).isOk());
  auto rgb = readPng8(dir / "grey.png", 3);
  ASSERT_TRUE(rgb.isOk());
  EXPECT_EQ(rgb->channels(), 3);
  EXPECT_EQ(rgb->data(), (std::vector<std::uint8_t>{0, 0, 0, 100, 100, 100, 255, 255, 255}));
  auto rgba = readPng8(dir / "grey.png", 4);
  ASSERT_TRUE(rgba.isOk());
  EXPECT_EQ(rgba->at(1, 0, 3), 255);
  EXPECT_EQ(readPng8(dir / "grey.png", 5).status().code(), StatusCode::kInvalidArgument);
}

TEST(Png, SixteenBitGreyRoundTripExact) {
  test::TempDir dir;
  ImageU16 image(4, 3, 1);
  const std::vector<std::uint16_t> values{0, 1, 255, 256, 257, 1000, 4095, 32767, 32768, 40000, 65534, 65535};
  image.data() = values;
  ASSERT_TRUE(writePng(dir / "depth.png", image).isOk());
  auto read = readPng16(dir / "depth.png");
  ASSERT_TRUE(read.isOk()) << read.status().toString();
  EXPECT_EQ(read->width(), 4);
  EXPECT_EQ(read->height(), 3);
  EXPECT_EQ(read->channels(), 1);
  EXPECT_EQ(read->data(), values);
  EXPECT_EQ(read->at(3, 2), 65535);
  EXPECT_EQ(read->at(1, 1), 1000);

  // The 8-bit reader keeps the high byte.
  auto eight = readPng8(dir / "depth.png");
  ASSERT_TRUE(eight.isOk());
  EXPECT_EQ(eight->at(1, 1), 1000 >> 8);
  EXPECT_EQ(eight->at(3, 2), 255);
}

TEST(Png, SixteenBitReaderKeepsEightBitValues) {
  test::TempDir dir;
  ImageU8 labels(3, 1, 1);
  labels.data() = {0, 7, 255};
  ASSERT_TRUE(writePng(dir / "labels.png", labels).isOk());
  auto read = readPng16(dir / "labels.png");
  ASSERT_TRUE(read.isOk());
  EXPECT_EQ(read->data(), (std::vector<std::uint16_t>{0, 7, 255}));

  ASSERT_TRUE(writePng(dir / "colour.png", pattern8(2, 2, 3)).isOk());
  auto colour = readPng16(dir / "colour.png");
  ASSERT_FALSE(colour.isOk());
  EXPECT_NE(colour.status().message().find("colour.png"), std::string::npos);
  EXPECT_NE(colour.status().message().find("single-channel"), std::string::npos) << colour.status().message();
}

TEST(Png, BadInputNamesTheFile) {
  test::TempDir dir;
  auto missing = readPng8(dir / "absent.png");
  ASSERT_FALSE(missing.isOk());
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
  EXPECT_NE(missing.status().message().find("absent.png"), std::string::npos);
  EXPECT_EQ(readPng16(dir / "absent16.png").status().code(), StatusCode::kNotFound);

  std::ofstream(dir / "text.png") << "this is not an image\n";
  for (const auto& status : {readPng8(dir / "text.png").status(), readPng16(dir / "text.png").status()}) {
    EXPECT_EQ(status.code(), StatusCode::kParseError);
    EXPECT_NE(status.message().find("text.png: not a PNG file"), std::string::npos) << status.message();
  }

  ImageU16 depth(64, 64, 1, 1234);
  ASSERT_TRUE(writePng(dir / "full.png", depth).isOk());
  const std::string bytes = slurp(dir / "full.png");
  for (const std::size_t size : {std::size_t{8}, std::size_t{30}, bytes.size() / 2, bytes.size() - 13}) {
    SCOPED_TRACE(size);
    std::ofstream(dir / "cut.png", std::ios::binary | std::ios::trunc) << bytes.substr(0, size);
    auto cut16 = readPng16(dir / "cut.png");
    ASSERT_FALSE(cut16.isOk());
    EXPECT_NE(cut16.status().message().find("cut.png"), std::string::npos);
    auto cut8 = readPng8(dir / "cut.png");
    ASSERT_FALSE(cut8.isOk());
    EXPECT_NE(cut8.status().message().find("cut.png"), std::string::npos);
  }
}

TEST(Png, WriteRejectsWhatPngCannotHold) {
  test::TempDir dir;
  const Status empty = writePng(dir / "empty.png", ImageU8());
  EXPECT_EQ(empty.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(empty.message().find("empty.png"), std::string::npos);
  const Status rgb16 = writePng(dir / "rgb16.png", ImageU16(2, 2, 3));
  EXPECT_EQ(rgb16.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(rgb16.message().find("1 channel"), std::string::npos);
  const Status no_dir = writePng(dir / "no" / "such" / "dir.png", pattern8(2, 2, 1));
  EXPECT_EQ(no_dir.code(), StatusCode::kIoError);
  EXPECT_NE(no_dir.message().find("dir.png"), std::string::npos);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace artemis::io
