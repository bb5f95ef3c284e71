#include "artemis/datasets/compressed_image.hpp"

#include <climits>
#include <cstring>
#include <memory>

#define STB_IMAGE_STATIC  // this file's own copy: no stbi_ symbols for another to clash with
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_JPEG
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wuseless-cast"
#pragma GCC diagnostic ignored "-Wcast-qual"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace artemis::datasets {

namespace {
constexpr long long kMaxPixels = 1LL << 26;
}

Result<ImageU8> decodeCompressedPicture(std::span<const std::uint8_t> bytes, const std::string& what) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) return parseError(what + ": a picture of over 2 GB");
  const auto size = static_cast<int>(bytes.size());
  int width = 0;
  int height = 0;
  int channels = 0;
  if (stbi_info_from_memory(bytes.data(), size, &width, &height, &channels) == 0) {
    return parseError(what + ": not a JPEG or PNG picture (" + stbi_failure_reason() + ")");
  }
  if (width <= 0 || height <= 0 || static_cast<long long>(width) * height > kMaxPixels) {
    return parseError(what + ": a picture of " + std::to_string(width) + "x" + std::to_string(height) + " pixels");
  }
  const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), size, &width, &height, &channels, 3), stbi_image_free);
  if (pixels == nullptr) return parseError(what + ": cannot decode the picture (" + stbi_failure_reason() + ")");
  ImageU8 rgb(width, height, 3);
  std::memcpy(rgb.data().data(), pixels.get(), rgb.data().size());
  return rgb;
}

}  // namespace artemis::datasets
