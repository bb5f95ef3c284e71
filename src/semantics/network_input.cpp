#include "artemis/semantics/network_input.hpp"

#include <algorithm>
#include <cmath>

namespace artemis::semantics {

Placement placeImage(int image_width, int image_height, const NetworkInput& input) {
  Placement p;
  p.image_width = image_width;
  p.image_height = image_height;
  if (image_width <= 0 || image_height <= 0) return p;
  const double sx = static_cast<double>(input.width) / image_width;
  const double sy = static_cast<double>(input.height) / image_height;
  if (!input.letterbox) {
    p.scale_x = sx;
    p.scale_y = sy;
    return p;
  }
  // YOLO's letterbox: one scale, the scaled image rounded to whole pixels and centred.
  const double s = std::min(sx, sy);
  const double w = std::max(1.0, std::round(image_width * s));  // a 1 x 2000 image still has a row
  const double h = std::max(1.0, std::round(image_height * s));
  p.scale_x = w / image_width;
  p.scale_y = h / image_height;
  p.pad_x = std::floor((input.width - w) / 2.0);
  p.pad_y = std::floor((input.height - h) / 2.0);
  return p;
}

Placement fillInput(const ImageU8& rgb, const NetworkInput& input, onnx::Tensor& out,
                    const std::array<int, 3>* pad_rgb) {
  const Placement p = placeImage(rgb.width(), rgb.height(), input);
  const int w = input.width;
  const int h = input.height;
  const auto plane = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  out.type = onnx::ElementType::kFloat;
  out.shape = {1, 3, h, w};
  out.values.resize(3 * plane);
  out.ints.clear();
  std::array<float, 3> a{};
  std::array<float, 3> b{};
  for (int c = 0; c < 3; ++c) {
    const std::size_t k = static_cast<std::size_t>(c);
    a[k] = static_cast<float>(input.scale / input.std[k]);
    b[k] = static_cast<float>(-input.mean[k] / input.std[k]);
  }
  const auto value = [&](int c, float pixel) {
    return pixel * a[static_cast<std::size_t>(c)] + b[static_cast<std::size_t>(c)];
  };
  // Plane c of the tensor takes image channel c, or 2 - c in BGR order.
  const auto source = [&](int c) { return input.bgr ? 2 - c : c; };
  const int x0 = static_cast<int>(p.pad_x);
  const int y0 = static_cast<int>(p.pad_y);
  const int x1 = std::min(w, static_cast<int>(std::lround(p.pad_x + rgb.width() * p.scale_x)));
  const int y1 = std::min(h, static_cast<int>(std::lround(p.pad_y + rgb.height() * p.scale_y)));
  for (int c = 0; c < 3; ++c) {
    float* dst = out.values.data() + static_cast<std::size_t>(c) * plane;
    const float pad = value(
        c, static_cast<float>(pad_rgb != nullptr ? (*pad_rgb)[static_cast<std::size_t>(source(c))] : input.pad_value));
    std::fill(dst, dst + plane, pad);
  }
  if (rgb.empty()) return p;
  const int iw = rgb.width();
  const int ih = rgb.height();
  for (int y = std::max(0, y0); y < y1; ++y) {
    // The image position of this input pixel's centre.
    const double fy = std::clamp(p.imageY(y + 0.5) - 0.5, 0.0, static_cast<double>(ih - 1));
    const int ya = static_cast<int>(fy);
    const int yb = std::min(ya + 1, ih - 1);
    const auto ty = static_cast<float>(fy - ya);
    for (int x = std::max(0, x0); x < x1; ++x) {
      const double fx = std::clamp(p.imageX(x + 0.5) - 0.5, 0.0, static_cast<double>(iw - 1));
      const std::size_t at = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
      if (input.nearest) {
        const int u = std::clamp(static_cast<int>(std::lround(fx)), 0, iw - 1);
        const int v = std::clamp(static_cast<int>(std::lround(fy)), 0, ih - 1);
        for (int c = 0; c < 3; ++c) {
          out.values[static_cast<std::size_t>(c) * plane + at] = value(c, rgb.at(u, v, source(c)));
        }
        continue;
      }
      const int xa = static_cast<int>(fx);
      const int xb = std::min(xa + 1, iw - 1);
      const auto tx = static_cast<float>(fx - xa);
      for (int c = 0; c < 3; ++c) {
        const int s = source(c);
        const float top = (1 - tx) * rgb.at(xa, ya, s) + tx * rgb.at(xb, ya, s);
        const float bottom = (1 - tx) * rgb.at(xa, yb, s) + tx * rgb.at(xb, yb, s);
        out.values[static_cast<std::size_t>(c) * plane + at] = value(c, (1 - ty) * top + ty * bottom);
      }
    }
  }
  return p;
}

}  // namespace artemis::semantics
