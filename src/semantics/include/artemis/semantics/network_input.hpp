#pragma once
// A camera image as a network's input tensor ([1, 3, height, width], planar), and the way back
// from the input's pixels to the image's. An image is letterboxed (scaled by one factor to fit,
// aspect kept, centred on a pad colour, as YOLO and FastSAM are trained) or stretched to the size;
// values are (pixel * scale - mean) / std per channel, in RGB or BGR order.
//
// Coordinates are continuous, pixel centres at k + 0.5: image x maps to input x * scale_x + pad_x.

#include <array>
#include <string>

#include "artemis/core/image.hpp"
#include "artemis/semantics/onnx_runtime.hpp"

namespace artemis::semantics {

struct NetworkInput {
  std::string name;  // the model's input; empty: its only input
  int width = 640;
  int height = 640;
  bool letterbox = true;  // false: stretch to width x height
  int pad_value = 114;    // 0..255, the letterbox's border
  double scale = 1.0 / 255.0;
  // Per plane of the tensor, in channel_order (with bgr, mean[0] is blue's).
  std::array<double, 3> mean{0.0, 0.0, 0.0};
  std::array<double, 3> std{1.0, 1.0, 1.0};
  bool bgr = false;
  bool nearest = false;  // resize by nearest pixel (class-coded images) instead of bilinear
};

// Where an image of image_width x image_height sits in the input.
struct Placement {
  double scale_x = 1.0;
  double scale_y = 1.0;
  double pad_x = 0.0;
  double pad_y = 0.0;
  int image_width = 0;
  int image_height = 0;
  [[nodiscard]] double inputX(double image_x) const { return image_x * scale_x + pad_x; }
  [[nodiscard]] double inputY(double image_y) const { return image_y * scale_y + pad_y; }
  [[nodiscard]] double imageX(double input_x) const { return (input_x - pad_x) / scale_x; }
  [[nodiscard]] double imageY(double input_y) const { return (input_y - pad_y) / scale_y; }
};

// Where an image of this size goes in `input`.
Placement placeImage(int image_width, int image_height, const NetworkInput& input);

// The RGB image (3 channels, 8 bits) as the input tensor; `pad_rgb` (when not null) replaces the
// pad value, per channel. Writes into `out` (its storage reused) and returns the placement.
Placement fillInput(const ImageU8& rgb, const NetworkInput& input, onnx::Tensor& out,
                    const std::array<int, 3>* pad_rgb = nullptr);

}  // namespace artemis::semantics
