// PNG reading through libpng, row by row. A decompression bomb (a small file whose data inflates
// to gigabytes) costs no more than the image it claims to be, and that claim is checked before any
// pixel memory is allocated: at most kMaxPixels, and no more raw bytes than the file could hold
// (deflate expands at most 1032:1). 8-bit reads expand palettes, transparency and low bit depths,
// reduce 16-bit samples to their high byte, and convert channel counts as stb_image does (grey is
// 77 R + 150 G + 29 B over 256); 16-bit reads keep 8-bit grey values as they are. libpng reports
// errors by longjmp, so each libpng call sequence lives in a small function whose frame holds
// nothing with a destructor.

#include <png.h>

#include <algorithm>
#include <bit>
#include <csetjmp>
#include <cstdint>
#include <cstring>
#include <string>

#include "artemis/io/png.hpp"
#include "artemis/io/read_file.hpp"
#include "png_detail.hpp"

namespace artemis::io {

namespace {

using detail::PngContext;
using detail::PngHeader;

constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
// 2^26 pixels (8192 x 8192): 256 MiB as RGBA, far beyond any camera this reads.
constexpr std::uint64_t kMaxPixels = std::uint64_t{1} << 26;
// zlib's deflate cannot expand data by more than about 1032:1.
constexpr std::uint64_t kMaxInflation = 1032;
// The largest ancillary chunk libpng may allocate while reading.
constexpr png_alloc_size_t kMaxChunkBytes = 8u << 20;
// Ancillary chunks skipped as if unknown: all but tRNS (transparency becomes alpha).
constexpr png_byte kSkippedChunks[] =
    "iCCP\0zTXt\0iTXt\0tEXt\0sPLT\0eXIf\0pCAL\0sCAL\0hIST\0tIME\0oFFs\0pHYs\0"
    "sBIT\0cHRM\0gAMA\0sRGB\0bKGD";
constexpr int kSkippedChunkCount = 17;

// Set once the rows are being read: libpng asks for more compressed data after the last row to
// inflate whatever follows it (1 KB at a time, to the stream's end), which is where a bomb keeps its
// gigabytes. The rows are complete by then, so reading stops there, and the chunks after the image
// (nothing this reader uses) are not read.
struct RowsContext : PngContext {
  bool reading_rows = false;
  bool interlaced = false;
  png_uint_32 height = 0;
  bool rows_complete = false;
};

bool allRowsRead(png_structp png, const RowsContext& context) {
  if (context.interlaced) return png_get_current_pass_number(png) >= 7;
  return png_get_current_row_number(png) >= context.height;
}

void readFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* context = static_cast<RowsContext*>(png_get_io_ptr(png));
  if (context->reading_rows && allRowsRead(png, *context)) {
    context->rows_complete = true;
    png_error(png, "rows complete");
  }
  if (length > context->size - context->pos) png_error(png, "truncated file");
  std::memcpy(out, context->data + context->pos, length);
  context->pos += length;
}

// NOLINTBEGIN(cert-err52-cpp): setjmp is libpng's error protocol; these frames are trivial.
bool readHeader(png_structp png, png_infop info, PngHeader* header) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  png_get_IHDR(png, info, &header->width, &header->height, &header->bit_depth, &header->color_type, nullptr, nullptr,
               nullptr);
  return true;
}

// 8-bit samples: palette to RGB, transparency to alpha, low depths to 8, 16 to 8 bits.
bool prepare8(png_structp png, png_infop info, int* channels, std::size_t* row_bytes) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  *channels = png_get_channels(png, info);
  *row_bytes = png_get_rowbytes(png, info);
  return true;
}

// Grey samples, unpacked to one byte (depth <= 8) or two native-order bytes (16) each.
bool prepareGrey(png_structp png, png_infop info, std::size_t* row_bytes) {
  if (setjmp(png_jmpbuf(png))) return false;
  if (png_get_bit_depth(png, info) < 8) png_set_packing(png);
  if (png_get_bit_depth(png, info) == 16 && std::endian::native == std::endian::little) png_set_swap(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  *row_bytes = png_get_rowbytes(png, info);
  return true;
}

bool readRows(png_structp png, png_bytep* rows, RowsContext* context) {
  if (setjmp(png_jmpbuf(png))) return context->rows_complete;
  png_read_image(png, rows);
  return true;
}
// NOLINTEND(cert-err52-cpp)

int samplesPerPixel(int color_type) {
  switch (color_type) {
    case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
    case PNG_COLOR_TYPE_RGB: return 3;
    case PNG_COLOR_TYPE_RGB_ALPHA: return 4;
    default: return 1;  // grey, palette
  }
}

std::string sizeText(const PngHeader& header) {
  return std::to_string(header.width) + "x" + std::to_string(header.height);
}

// One libpng read of an in-memory file; the structs are freed on destruction.
class PngDecoder {
 public:
  PngDecoder(const std::vector<unsigned char>& bytes, std::string file) : file_(std::move(file)) {
    context_.data = bytes.data();
    context_.size = bytes.size();
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &context_, detail::onPngError, detail::onPngWarning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (info_ != nullptr) {
      png_set_read_fn(png_, &context_, readFromMemory);
      png_set_chunk_malloc_max(png_, kMaxChunkBytes);
      // Text, colour profiles and the like are never used here; libpng would still decompress
      // them (an ICC profile's header can claim 2 GB), so they are skipped unread.
      png_set_keep_unknown_chunks(png_, PNG_HANDLE_CHUNK_NEVER, kSkippedChunks, kSkippedChunkCount);
    }
  }
  ~PngDecoder() { png_destroy_read_struct(&png_, info_ != nullptr ? &info_ : nullptr, nullptr); }
  PngDecoder(const PngDecoder&) = delete;
  PngDecoder& operator=(const PngDecoder&) = delete;

  // The header, checked against the pixel limit and the file's size.
  Result<PngHeader> header() {
    if (info_ == nullptr) return ioError(file_ + ": cannot create a libpng reader");
    if (context_.size < sizeof(kSignature) || std::memcmp(context_.data, kSignature, sizeof(kSignature)) != 0) {
      return parseError(file_ + ": not a PNG file (bad signature)");
    }
    if (!hasEnd()) return parseError(file_ + ": truncated PNG (no IEND chunk at its end)");
    PngHeader header;
    if (!readHeader(png_, info_, &header)) return failed();
    const std::uint64_t pixels = std::uint64_t{header.width} * header.height;
    if (pixels > kMaxPixels) {
      return parseError(file_ + ": image too large (" + sizeText(header) + ", more than 2^26 pixels)");
    }
    const std::uint64_t bits = std::uint64_t{header.width} * static_cast<std::uint64_t>(header.bit_depth) *
                               static_cast<std::uint64_t>(samplesPerPixel(header.color_type));
    const std::uint64_t raw_bytes = header.height * (1 + (bits + 7) / 8);
    if (raw_bytes > kMaxInflation * context_.size) {
      return parseError(file_ + ": claims " + sizeText(header) + " pixels, more than a file of " +
                        std::to_string(context_.size) + " bytes can hold (damaged, or a decompression bomb)");
    }
    return header;
  }

  // All rows into `samples` (row_bytes each).
  Status read(std::size_t row_bytes, std::uint32_t height, std::vector<unsigned char>& samples) {
    samples.resize(row_bytes * height);
    std::vector<png_bytep> rows(height);
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = samples.data() + y * row_bytes;
    context_.reading_rows = true;
    context_.interlaced = png_get_interlace_type(png_, info_) != PNG_INTERLACE_NONE;
    context_.height = height;
    if (!readRows(png_, rows.data(), &context_)) return failed();
    return Status::ok();
  }

  // The rows are read without what follows them, so a cut file is recognised by its missing end:
  // the IEND chunk within the last 1 KiB (some writers append a few bytes after it).
  [[nodiscard]] bool hasEnd() const {
    static constexpr unsigned char kEnd[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    const std::size_t from = context_.size > 1024 ? context_.size - 1024 : 0;
    const auto* begin = context_.data + from;
    const auto* end = context_.data + context_.size;
    return std::search(begin, end, std::begin(kEnd), std::end(kEnd)) != end;
  }

  Status failed() const { return parseError(file_ + ": bad PNG: " + context_.message); }
  [[nodiscard]] png_structp png() const { return png_; }
  [[nodiscard]] png_infop info() const { return info_; }

 private:
  std::string file_;
  RowsContext context_;
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

unsigned char luminance(const unsigned char* rgb) {
  return static_cast<unsigned char>((rgb[0] * 77 + rgb[1] * 150 + rgb[2] * 29) >> 8);
}

// One pixel from `from` to `to` channels (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA).
void convertPixel(const unsigned char* in, int from, unsigned char* out, int to) {
  const bool colour_in = from >= 3;
  const bool alpha_in = from == 2 || from == 4;
  const unsigned char alpha = alpha_in ? in[from - 1] : 255;
  if (to >= 3) {
    for (int c = 0; c < 3; ++c) out[c] = colour_in ? in[c] : in[0];
  } else {
    out[0] = colour_in ? luminance(in) : in[0];
  }
  if (to == 2 || to == 4) out[to - 1] = alpha;
}

ImageU8 toImage(const std::vector<unsigned char>& samples, const PngHeader& header, int from, int to) {
  ImageU8 image(static_cast<int>(header.width), static_cast<int>(header.height), to);
  auto& out = image.data();
  if (from == to) {
    std::memcpy(out.data(), samples.data(), out.size());
    return image;
  }
  const std::size_t pixels = std::size_t{header.width} * header.height;
  const auto from_step = static_cast<std::size_t>(from);
  const auto to_step = static_cast<std::size_t>(to);
  for (std::size_t i = 0; i < pixels; ++i) convertPixel(&samples[i * from_step], from, &out[i * to_step], to);
  return image;
}

// The rows of an 8-bit grey, grey+alpha, RGB or RGBA image, not interlaced and without a tRNS chunk
// (transparency that would become alpha), read by quickRows8; else nothing (libpng reads it).
bool readQuickly(const std::vector<unsigned char>& bytes, PngDecoder& decoder, const PngHeader& header,
                 std::vector<unsigned char>& samples, int* channels) {
  if (header.color_type == PNG_COLOR_TYPE_PALETTE ||
      png_get_interlace_type(decoder.png(), decoder.info()) != PNG_INTERLACE_NONE ||
      png_get_valid(decoder.png(), decoder.info(), PNG_INFO_tRNS) != 0) {
    return false;
  }
  *channels = samplesPerPixel(header.color_type);
  return detail::quickRows8(bytes.data(), bytes.size(), header, *channels, samples);
}

Result<ImageU8> decode8(const std::vector<unsigned char>& bytes, const std::string& file, int desired_channels) {
  PngDecoder decoder(bytes, file);
  auto header = decoder.header();
  if (!header) return header.status();
  std::vector<unsigned char> quick;
  if (int channels = 0; readQuickly(bytes, decoder, *header, quick, &channels)) {
    return toImage(quick, *header, channels, desired_channels != 0 ? desired_channels : channels);
  }
  int channels = 0;
  std::size_t row_bytes = 0;
  if (!prepare8(decoder.png(), decoder.info(), &channels, &row_bytes)) return decoder.failed();
  if (channels < 1 || channels > 4 || row_bytes != std::size_t{header->width} * static_cast<std::size_t>(channels)) {
    return parseError(file + ": bad PNG: unexpected row layout");
  }
  std::vector<unsigned char> samples;
  if (Status s = decoder.read(row_bytes, header->height, samples); !s.isOk()) return s;
  return toImage(samples, *header, channels, desired_channels != 0 ? desired_channels : channels);
}

Result<ImageU16> decodeGrey16(const std::vector<unsigned char>& bytes, const std::string& file) {
  PngDecoder decoder(bytes, file);
  auto header = decoder.header();
  if (!header) return header.status();
  if (header->color_type != PNG_COLOR_TYPE_GRAY) {
    return parseError(file + ": expected a single-channel grey PNG, found colour type " +
                      std::to_string(header->color_type));
  }
  const bool wide = header->bit_depth == 16;
  std::size_t row_bytes = 0;
  if (!prepareGrey(decoder.png(), decoder.info(), &row_bytes)) return decoder.failed();
  if (row_bytes != std::size_t{header->width} * (wide ? 2 : 1)) {
    return parseError(file + ": bad PNG: unexpected row layout");
  }
  std::vector<unsigned char> samples;
  if (Status s = decoder.read(row_bytes, header->height, samples); !s.isOk()) return s;

  ImageU16 image(static_cast<int>(header->width), static_cast<int>(header->height), 1);
  auto& pixels = image.data();
  if (wide) {
    std::memcpy(pixels.data(), samples.data(), samples.size());
  } else {
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = samples[i];  // values kept, not rescaled
  }
  return image;
}

}  // namespace

Result<ImageU8> readPng8(const std::filesystem::path& path, int desired_channels) {
  const std::string file = path.string();
  if (desired_channels < 0 || desired_channels > 4) {
    return invalidArgument(file + ": desired channels must be 0..4, not " + std::to_string(desired_channels));
  }
  auto bytes = readFileBytes(path, limits::kImage);
  if (!bytes) return bytes.status();
  return decode8(*bytes, file, desired_channels);
}

Result<ImageU16> readPng16(const std::filesystem::path& path) {
  auto bytes = readFileBytes(path, limits::kImage);
  if (!bytes) return bytes.status();
  return decodeGrey16(*bytes, path.string());
}

}  // namespace artemis::io
