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
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wuseless-cast"
#endif
#pragma GCC diagnostic ignored "-Wcast-qual"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace artemis::datasets {

namespace {

constexpr long long kMaxPixels = 1LL << 26;

// Whether every Huffman table (DHT segment) that stb_image could meet in these bytes declares at
// most 256 codes, as the JPEG standard requires. Debian's stb_image builds each table into an
// array of 257 without that check, so a damaged or hostile table writes past it (found by
// fuzz_ros_messages). stb_image skips bytes that are not markers and reads zeros past the end, so
// every 0xFF (0xFF...) 0xC4 of the input is taken as a table here, with zeros past the end. In a
// valid JPEG that is no more than its tables: entropy-coded data never holds 0xFF 0xC4.
bool huffmanTablesFit(std::span<const std::uint8_t> b) {
  // Only what stb_image takes for a JPEG: its start of image, 0xFF, any fill bytes, 0xD8. (A PNG's
  // compressed data may well hold 0xFF 0xC4.)
  std::size_t start = 0;
  while (start < b.size() && b[start] == 0xFF) ++start;
  if (start == 0 || start >= b.size() || b[start] != 0xD8) return true;
  const auto at = [&](std::size_t i) -> std::size_t { return i < b.size() ? b[i] : 0; };
  for (std::size_t p = 0; p + 1 < b.size(); ++p) {
    if (b[p] != 0xFF || b[p + 1] != 0xC4) continue;
    const std::size_t segment = p + 2;  // its length, then tables of a class byte, 16 counts, symbols
    const std::size_t end = segment + ((at(segment) << 8) | at(segment + 1));
    for (std::size_t q = segment + 2; q < end && q < b.size();) {
      std::size_t codes = 0;
      for (std::size_t i = 1; i <= 16; ++i) codes += at(q + i);
      if (codes > 256) return false;
      q += 17 + codes;
    }
  }
  return true;
}

}  // namespace

Result<ImageU8> decodeCompressedPicture(std::span<const std::uint8_t> bytes, const std::string& what) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) return parseError(what + ": a picture of over 2 GB");
  const auto size = static_cast<int>(bytes.size());
  if (!huffmanTablesFit(bytes)) {
    return parseError(what + ": a JPEG Huffman table of more than 256 codes");
  }
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
