#pragma once
// A dense, row-major, interleaved image: 8-bit colour or grey, 16-bit grey (labels, depth).

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace artemis {

template <typename T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, int channels, T fill = T{}) : width_(width), height_(height), channels_(channels) {
    if (width < 0 || height < 0 || channels < 1 || channels > 4) {
      throw std::invalid_argument("Image: bad size " + std::to_string(width) + "x" + std::to_string(height) + "x" +
                                  std::to_string(channels));
    }
    data_.assign(
        static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels), fill);
  }

  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  [[nodiscard]] int channels() const { return channels_; }
  [[nodiscard]] bool empty() const { return data_.empty(); }
  [[nodiscard]] bool contains(int u, int v) const { return u >= 0 && v >= 0 && u < width_ && v < height_; }

  // Pixel (u = column, v = row), channel c. No bounds check: use contains() first.
  T& at(int u, int v, int c = 0) { return data_[index(u, v, c)]; }
  const T& at(int u, int v, int c = 0) const { return data_[index(u, v, c)]; }

  std::vector<T>& data() { return data_; }
  [[nodiscard]] const std::vector<T>& data() const { return data_; }

 private:
  [[nodiscard]] std::size_t index(int u, int v, int c) const {
    return (static_cast<std::size_t>(v) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(u)) *
               static_cast<std::size_t>(channels_) +
           static_cast<std::size_t>(c);
  }

  int width_ = 0;
  int height_ = 0;
  int channels_ = 0;
  std::vector<T> data_;
};

using ImageU8 = Image<std::uint8_t>;
using ImageU16 = Image<std::uint16_t>;
using ImageF32 = Image<float>;

}  // namespace artemis
