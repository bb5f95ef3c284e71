// A camera image as a network's input: YOLO's letterbox (one scale, centred, the pad colour), the
// way back to image pixels, stretching, per-plane mean and deviation, and BGR order.
#include "artemis/semantics/network_input.hpp"

#include <gtest/gtest.h>

namespace artemis::semantics {
namespace {

float plane(const onnx::Tensor& t, int c, int x, int y) {
  const auto w = static_cast<std::size_t>(t.shape[3]);
  const auto h = static_cast<std::size_t>(t.shape[2]);
  return t.values[static_cast<std::size_t>(c) * w * h + static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x)];
}

TEST(NetworkInput, LetterboxScalesOnceCentresAndMapsBack) {
  NetworkInput in;
  in.width = 128;
  in.height = 128;
  // 256 x 192 -> 128 x 96, 16 rows of padding above and below.
  const Placement p = placeImage(256, 192, in);
  EXPECT_DOUBLE_EQ(p.scale_x, 0.5);
  EXPECT_DOUBLE_EQ(p.scale_y, 0.5);
  EXPECT_DOUBLE_EQ(p.pad_x, 0.0);
  EXPECT_DOUBLE_EQ(p.pad_y, 16.0);
  EXPECT_DOUBLE_EQ(p.imageX(p.inputX(37.25)), 37.25);
  EXPECT_DOUBLE_EQ(p.imageY(40.0), 48.0);
  // A sliver of an image keeps a row; stretching scales each axis.
  EXPECT_GT(placeImage(2000, 1, in).scale_y, 0.0);
  in.letterbox = false;
  const Placement s = placeImage(256, 192, in);
  EXPECT_DOUBLE_EQ(s.scale_y, 128.0 / 192.0);
  EXPECT_DOUBLE_EQ(s.pad_y, 0.0);
}

TEST(NetworkInput, ValuesPerPlaneInChannelOrderAndThePadColour) {
  // A 4 x 2 image, red on the left half and blue on the right, into an 8 x 8 letterbox (4 x 4 of it
  // image, 2 rows of pad above and below).
  ImageU8 image(4, 2, 3, 0);
  for (int v = 0; v < 2; ++v) {
    for (int u = 0; u < 4; ++u) image.at(u, v, u < 2 ? 0 : 2) = 200;
  }
  NetworkInput in;
  in.width = 8;
  in.height = 8;
  in.nearest = true;
  in.scale = 1.0 / 100.0;
  in.mean = {0.5, 0.25, 0.0};  // per plane
  in.std = {2.0, 1.0, 1.0};
  onnx::Tensor t;
  fillInput(image, in, t);
  ASSERT_EQ(t.shape, (std::vector<std::int64_t>{1, 3, 8, 8}));
  EXPECT_FLOAT_EQ(plane(t, 0, 1, 3), (2.0f - 0.5f) / 2.0f);  // red, left
  EXPECT_FLOAT_EQ(plane(t, 2, 6, 3), 2.0f);                  // blue, right
  EXPECT_FLOAT_EQ(plane(t, 2, 1, 3), 0.0f);
  EXPECT_FLOAT_EQ(plane(t, 1, 1, 0), 1.14f - 0.25f);  // the pad row: 114 / 100, less the mean
  // BGR: plane 0 is blue.
  in.bgr = true;
  fillInput(image, in, t);
  EXPECT_FLOAT_EQ(plane(t, 0, 6, 3), (2.0f - 0.5f) / 2.0f);
  EXPECT_FLOAT_EQ(plane(t, 2, 1, 3), 2.0f);
  EXPECT_FLOAT_EQ(plane(t, 0, 1, 3), -0.25f);
}

}  // namespace
}  // namespace artemis::semantics
