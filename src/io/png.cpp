// PNG: stb_image decodes 8-bit reads (it converts between channel counts and reduces 16-bit
// files); libpng does 16-bit reads (stb would rescale 8-bit files by 257, we keep the values)
// and all writes (stb_image_write cannot write 16-bit). libpng reports errors by longjmp, so each
// libpng call sequence lives in a small function whose frame holds nothing with a destructor.

#include "artemis/io/png.hpp"

#include <png.h>
#include <stb_image.h>

#include <bit>
#include <csetjmp>
#include <cstring>
#include <limits>

#include "file_util.hpp"

namespace artemis::io {

namespace {

constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

// Where libpng's error message goes; io points at the data being read.
struct PngContext {
  char message[256] = "unknown libpng error";
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  std::vector<unsigned char>* out = nullptr;
};

void onPngError(png_structp png, png_const_charp message) {
  auto* context = static_cast<PngContext*>(png_get_error_ptr(png));
  std::strncpy(context->message, message, sizeof(context->message) - 1);
  context->message[sizeof(context->message) - 1] = '\0';
  png_longjmp(png, 1);
}

void onPngWarning(png_structp /*png*/, png_const_charp /*message*/) {}

void readFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
  if (length > context->size - context->pos) png_error(png, "truncated file");
  std::memcpy(out, context->data + context->pos, length);
  context->pos += length;
}

void writeToMemory(png_structp png, png_bytep data, png_size_t length) {
  auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
  context->out->insert(context->out->end(), data, data + length);
}

void flushNothing(png_structp /*png*/) {}

struct PngHeader {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = 0;
};

// NOLINTBEGIN(cert-err52-cpp): setjmp is libpng's error protocol; these frames are trivial.
bool readHeader(png_structp png, png_infop info, PngHeader* header) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  png_get_IHDR(png, info, &header->width, &header->height, &header->bit_depth, &header->color_type, nullptr, nullptr,
               nullptr);
  return true;
}

// Reads grey samples, unpacked to one byte (depth <= 8) or two native-order bytes (16) each.
bool readGreyRows(png_structp png, png_infop info, png_bytep* rows, std::size_t row_bytes) {
  if (setjmp(png_jmpbuf(png))) return false;
  if (png_get_bit_depth(png, info) < 8) png_set_packing(png);
  if (png_get_bit_depth(png, info) == 16 && std::endian::native == std::endian::little) png_set_swap(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != row_bytes) png_error(png, "unexpected row size");
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  return true;
}

bool encode(png_structp png, png_infop info, const PngHeader* header, png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, header->width, header->height, header->bit_depth, header->color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // zlib level 3 instead of the default 6: about twice as fast for a few per cent larger files,
  // which matters when a sequence writes four images a frame.
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}
// NOLINTEND(cert-err52-cpp)

Status checkSignature(const std::vector<unsigned char>& bytes, const std::string& file) {
  if (bytes.size() < sizeof(kSignature) || std::memcmp(bytes.data(), kSignature, sizeof(kSignature)) != 0) {
    return parseError(file + ": not a PNG file (bad signature)");
  }
  return Status::ok();
}

Result<ImageU16> decodeGrey16(const std::vector<unsigned char>& bytes, const std::string& file) {
  PngContext context;
  context.data = bytes.data();
  context.size = bytes.size();
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &context, onPngError, onPngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return ioError(file + ": cannot create a libpng reader");
  }
  png_set_read_fn(png, &context, readFromMemory);
  const auto fail = [&](const std::string& problem) {
    png_destroy_read_struct(&png, &info, nullptr);
    return Result<ImageU16>(parseError(file + ": " + problem));
  };
  PngHeader header;
  if (!readHeader(png, info, &header)) return fail(std::string("bad PNG: ") + context.message);
  if (header.color_type != PNG_COLOR_TYPE_GRAY) {
    return fail("expected a single-channel grey PNG, found colour type " + std::to_string(header.color_type));
  }
  constexpr auto kMaxSide = static_cast<png_uint_32>(std::numeric_limits<int>::max());
  if (header.width > kMaxSide || header.height > kMaxSide ||
      std::uint64_t{header.width} * header.height > (std::uint64_t{1} << 31)) {
    return fail("image too large (" + std::to_string(header.width) + "x" + std::to_string(header.height) + ")");
  }
  const bool wide = header.bit_depth == 16;
  const std::size_t row_bytes = std::size_t{header.width} * (wide ? 2 : 1);
  std::vector<unsigned char> samples(row_bytes * header.height);
  std::vector<png_bytep> rows(header.height);
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = samples.data() + y * row_bytes;
  if (!readGreyRows(png, info, rows.data(), row_bytes)) return fail(std::string("bad PNG: ") + context.message);
  png_destroy_read_struct(&png, &info, nullptr);

  ImageU16 image(static_cast<int>(header.width), static_cast<int>(header.height), 1);
  auto& pixels = image.data();
  if (wide) {
    std::memcpy(pixels.data(), samples.data(), samples.size());
  } else {
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = samples[i];  // values kept, not rescaled
  }
  return image;
}

Status encodeAndWrite(const std::filesystem::path& path, const PngHeader& header, std::vector<png_bytep>& rows) {
  const std::string file = path.string();
  std::vector<unsigned char> encoded;
  PngContext context;
  context.out = &encoded;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &context, onPngError, onPngWarning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return ioError(file + ": cannot create a libpng writer");
  }
  png_set_write_fn(png, &context, writeToMemory, flushNothing);
  const bool encoded_ok = encode(png, info, &header, rows.data());
  png_destroy_write_struct(&png, &info);
  if (!encoded_ok) return ioError(file + ": cannot encode PNG: " + context.message);

  detail::AtomicFile out;
  if (Status status = out.open(path); !status.isOk()) return status;
  if (Status status = out.write(encoded.data(), encoded.size()); !status.isOk()) return status;
  return out.commit();
}

template <typename T>
Status checkWritable(const std::string& file, const Image<T>& image) {
  if (image.width() <= 0 || image.height() <= 0) {
    return invalidArgument(file + ": cannot write an empty image (" + std::to_string(image.width()) + "x" +
                           std::to_string(image.height()) + ")");
  }
  return Status::ok();
}

}  // namespace

Result<ImageU8> readPng8(const std::filesystem::path& path, int desired_channels) {
  const std::string file = path.string();
  if (desired_channels < 0 || desired_channels > 4) {
    return invalidArgument(file + ": desired channels must be 0..4, not " + std::to_string(desired_channels));
  }
  auto bytes = detail::readFileBytes(path);
  if (!bytes) return bytes.status();
  if (Status status = checkSignature(*bytes, file); !status.isOk()) return status;
  if (bytes->size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    return parseError(file + ": file too large for the PNG decoder");
  }
  int width = 0;
  int height = 0;
  int file_channels = 0;
  stbi_uc* pixels = stbi_load_from_memory(bytes->data(), static_cast<int>(bytes->size()), &width, &height,
                                          &file_channels, desired_channels);
  if (pixels == nullptr) return parseError(file + ": bad PNG: " + stbi_failure_reason());
  const int channels = desired_channels != 0 ? desired_channels : file_channels;
  ImageU8 image(width, height, channels);
  std::memcpy(image.data().data(), pixels, image.data().size());
  stbi_image_free(pixels);
  return image;
}

Result<ImageU16> readPng16(const std::filesystem::path& path) {
  const std::string file = path.string();
  auto bytes = detail::readFileBytes(path);
  if (!bytes) return bytes.status();
  if (Status status = checkSignature(*bytes, file); !status.isOk()) return status;
  return decodeGrey16(*bytes, file);
}

Status writePng(const std::filesystem::path& path, const ImageU8& image) {
  if (Status status = checkWritable(path.string(), image); !status.isOk()) return status;
  constexpr int kColorTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGBA};
  const PngHeader header{static_cast<png_uint_32>(image.width()), static_cast<png_uint_32>(image.height()), 8,
                         kColorTypes[image.channels() - 1]};
  const std::size_t row_bytes = static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(image.channels());
  // libpng's API is not const-correct; it only reads the rows.
  auto* data = const_cast<unsigned char*>(image.data().data());
  std::vector<png_bytep> rows(header.height);
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = data + y * row_bytes;
  return encodeAndWrite(path, header, rows);
}

Status writePng(const std::filesystem::path& path, const ImageU16& image) {
  const std::string file = path.string();
  if (Status status = checkWritable(file, image); !status.isOk()) return status;
  if (image.channels() != 1) {
    return invalidArgument(file + ": 16-bit PNG writing supports 1 channel, image has " +
                           std::to_string(image.channels()));
  }
  const PngHeader header{static_cast<png_uint_32>(image.width()), static_cast<png_uint_32>(image.height()), 16,
                         PNG_COLOR_TYPE_GRAY};
  // PNG samples are big-endian, whatever the host.
  const auto& pixels = image.data();
  std::vector<unsigned char> big_endian(pixels.size() * 2);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    big_endian[2 * i] = static_cast<unsigned char>(pixels[i] >> 8);
    big_endian[2 * i + 1] = static_cast<unsigned char>(pixels[i] & 0xFF);
  }
  const std::size_t row_bytes = static_cast<std::size_t>(image.width()) * 2;
  std::vector<png_bytep> rows(header.height);
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = big_endian.data() + y * row_bytes;
  return encodeAndWrite(path, header, rows);
}

}  // namespace artemis::io
