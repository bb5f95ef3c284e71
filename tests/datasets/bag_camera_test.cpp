// A ROS camera's images as a bag run reads them: CameraInfo distortion undone by the remap table
// (checked against the models written out here independently), rectified images taken as they
// are with P's intrinsics, and CompressedImage pictures (PNG, JPEG) decoded, with clear errors.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "artemis/datasets/compressed_image.hpp"
#include "artemis/datasets/undistortion.hpp"
#include "artemis/io/png.hpp"
#include "support/test_support.hpp"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace artemis::datasets {
namespace {

// The public LiDAR-camera rig's 1280x1024 camera (radial-tangential), scaled down by 8.
ros::CameraInfo aviaCamera() {
  ros::CameraInfo info;
  info.width = 160;
  info.height = 128;
  info.distortion_model = "plumb_bob";
  info.D = {-0.07616, 0.123001, -0.00113, 0.000251, 0.0};
  info.K = {1293.57 / 8, 0, 626.91 / 8, 0, 1293.32 / 8, 522.80 / 8, 0, 0, 1};
  return info;
}

// A raw image whose pixel (u, v) holds u and v in red and green: bilinear resampling of it gives
// back the source coordinates a remap used, to within rounding.
ImageU8 coordinateRamp(int width, int height) {
  ImageU8 ramp(width, height, 3, 0);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      ramp.at(u, v, 0) = static_cast<std::uint8_t>(u);
      ramp.at(u, v, 1) = static_cast<std::uint8_t>(v);
    }
  }
  return ramp;
}

TEST(BagCamera, RadialTangentialAndFisheyeDistortionAreUndone) {
  for (const bool fisheye : {false, true}) {
    SCOPED_TRACE(fisheye ? "equidistant" : "plumb_bob");
    ros::CameraInfo info = aviaCamera();
    info.D = {-0.3, 0.1, 0.002, -0.001, 0.0};  // a wide-angle lens: shifts of pixels, not fractions
    if (fisheye) {
      info.distortion_model = "equidistant";
      info.D = {-0.2, 0.05, 0.0, 0.0};
    }
    auto undistortion = Undistortion::fromCameraInfo(info);
    ASSERT_TRUE(undistortion) << undistortion.status().message();
    EXPECT_FALSE(undistortion->identity());
    EXPECT_DOUBLE_EQ(undistortion->camera().fx_px, info.K[0]);
    auto out = undistortion->apply(coordinateRamp(info.width, info.height));
    ASSERT_TRUE(out) << out.status().message();
    const double fx = info.K[0], fy = info.K[4], cx = info.K[2], cy = info.K[5];
    double largest_shift = 0.0;
    for (int v = 4; v < info.height - 4; v += 8) {
      for (int u = 4; u < info.width - 4; u += 8) {
        const double x = (u - cx) / fx;
        const double y = (v - cy) / fy;
        double xd = x, yd = y;
        if (fisheye) {
          const double r = std::hypot(x, y);
          const double t = std::atan(r);
          const double td = t * (1 + info.D[0] * t * t + info.D[1] * std::pow(t, 4));
          xd = r > 0 ? x * td / r : x;
          yd = r > 0 ? y * td / r : y;
        } else {
          const double r2 = x * x + y * y;
          const double radial = 1 + info.D[0] * r2 + info.D[1] * r2 * r2;
          xd = x * radial + 2 * info.D[2] * x * y + info.D[3] * (r2 + 2 * x * x);
          yd = y * radial + info.D[2] * (r2 + 2 * y * y) + 2 * info.D[3] * x * y;
        }
        const double su = fx * xd + cx;
        const double sv = fy * yd + cy;
        if (su < 1 || sv < 1 || su > info.width - 2 || sv > info.height - 2) continue;
        largest_shift = std::max(largest_shift, std::hypot(su - u, sv - v));
        EXPECT_NEAR(out->at(u, v, 0), su, 0.6) << u << "," << v;
        EXPECT_NEAR(out->at(u, v, 1), sv, 0.6) << u << "," << v;
      }
    }
    EXPECT_GT(largest_shift, 3.0);  // the check can tell a model from none
  }
}

TEST(BagCamera, RectifiedImagesKeepPAndBadCalibrationsAreRefused) {
  ros::CameraInfo info = aviaCamera();
  info.D = {0, 0, 0, 0, 0};
  info.P = {150, 0, 80, 0, 0, 151, 64, 0, 0, 0, 1, 0};
  auto rectified = Undistortion::fromCameraInfo(info);
  ASSERT_TRUE(rectified);
  EXPECT_TRUE(rectified->identity());
  EXPECT_DOUBLE_EQ(rectified->camera().fx_px, 150.0);
  EXPECT_DOUBLE_EQ(rectified->camera().fy_px, 151.0);
  const ImageU8 ramp = coordinateRamp(160, 128);
  auto same = rectified->apply(ramp);
  ASSERT_TRUE(same);
  EXPECT_TRUE(same->data() == ramp.data());
  const auto wrong_size = rectified->apply(ImageU8(32, 32, 3));
  ASSERT_FALSE(wrong_size);
  EXPECT_NE(wrong_size.status().message().find("32x32"), std::string::npos);

  const auto refused = [&](ros::CameraInfo bad, const std::string& expected) {
    const auto u = Undistortion::fromCameraInfo(bad);
    ASSERT_FALSE(u) << expected;
    EXPECT_NE(u.status().message().find(expected), std::string::npos) << u.status().message();
  };
  ros::CameraInfo model = aviaCamera();
  model.distortion_model = "kannala_brandt_9";
  refused(model, "\"kannala_brandt_9\"");
  ros::CameraInfo three = aviaCamera();
  three.D = {0.1, 0.2, 0.3};
  refused(three, "3 coefficients");
  ros::CameraInfo flat = aviaCamera();
  flat.K[0] = 0;
  refused(flat, "intrinsics");
  ros::CameraInfo empty = aviaCamera();
  empty.width = 0;
  refused(empty, "image size");
  ros::CameraInfo huge = aviaCamera();  // a lying CameraInfo must not allocate a 16 GB remap table
  huge.width = 65536;
  huge.height = 32768;
  refused(huge, "image size 65536x32768");
}

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

TEST(BagCamera, CompressedPicturesDecodeAndGarbageIsAnError) {
  ImageU8 picture(40, 30, 3);
  for (int v = 0; v < 30; ++v) {
    for (int u = 0; u < 40; ++u) {
      picture.at(u, v, 0) = static_cast<std::uint8_t>(6 * u);
      picture.at(u, v, 1) = static_cast<std::uint8_t>(8 * v);
      picture.at(u, v, 2) = 90;
    }
  }
  test::TempDir tmp;
  ASSERT_TRUE(io::writePng(tmp / "p.png", picture).isOk());
  std::ifstream in(tmp / "p.png", std::ios::binary);
  const std::vector<std::uint8_t> png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto decoded = decodeCompressedPicture(png, "png");
  ASSERT_TRUE(decoded) << decoded.status().message();
  EXPECT_TRUE(decoded->data() == picture.data());  // lossless

  std::vector<std::uint8_t> jpeg;
  ASSERT_NE(stbi_write_jpg_to_func(appendBytes, &jpeg, 40, 30, 3, picture.data().data(), 95), 0);
  decoded = decodeCompressedPicture(jpeg, "jpeg");
  ASSERT_TRUE(decoded) << decoded.status().message();
  ASSERT_EQ(decoded->width(), 40);
  ASSERT_EQ(decoded->height(), 30);
  double error = 0.0;
  for (std::size_t k = 0; k < picture.data().size(); ++k) {
    error += std::abs(static_cast<int>(decoded->data()[k]) - static_cast<int>(picture.data()[k]));
  }
  EXPECT_LT(error / static_cast<double>(picture.data().size()), 4.0);  // lossy, but the same picture

  const std::vector<std::uint8_t> garbage(100, 0x42);
  const auto bad = decodeCompressedPicture(garbage, "bag.bag: /camera message 3");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.status().message().find("bag.bag: /camera message 3: not a JPEG or PNG"), std::string::npos)
      << bad.status().message();
  // A Huffman table of 512 codes (the standard allows 256), which Debian's stb_image would build
  // past the end of its table: refused before stb_image sees it.
  std::vector<std::uint8_t> hostile = {0xFF, 0xD8, 0xFF, 0xC4, 0x00, 0x13, 0x00};
  hostile.insert(hostile.end(), 16, 0x20);
  const auto huffman = decodeCompressedPicture(hostile, "hostile");
  ASSERT_FALSE(huffman);
  EXPECT_NE(huffman.status().message().find("Huffman table of more than 256 codes"), std::string::npos)
      << huffman.status().message();
  // ... and only in a JPEG: a PNG may hold those bytes (here after its end) and still decodes.
  std::vector<std::uint8_t> png_with_tail = png;
  png_with_tail.insert(png_with_tail.end(), hostile.begin(), hostile.end());
  const auto tail = decodeCompressedPicture(png_with_tail, "png with a tail");
  ASSERT_TRUE(tail) << tail.status().message();
  EXPECT_TRUE(tail->data() == picture.data());
  const auto cut = decodeCompressedPicture(std::span(jpeg.data(), jpeg.size() / 3), "cut");
  EXPECT_FALSE(cut && cut->width() == 40 && cut->data() == decoded->data());
}

}  // namespace
}  // namespace artemis::datasets
