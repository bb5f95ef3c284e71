#pragma once
// Private to the io module: what PNG reading and writing share around libpng.

#include <png.h>

#include <cstddef>
#include <vector>

namespace artemis::io::detail {

// Where libpng's error message goes; io points at the data being read or the bytes written.
struct PngContext {
  char message[256] = "unknown libpng error";
  const unsigned char* data = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  std::vector<unsigned char>* out = nullptr;
};

// libpng error callbacks: the error keeps the message and longjmps; warnings are dropped.
void onPngError(png_structp png, png_const_charp message);
void onPngWarning(png_structp png, png_const_charp message);

struct PngHeader {
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = 0;
};

// The rows of a PNG file (`data`, `size` bytes, whose header says `header`) of 8-bit samples,
// `channels` a pixel, not interlaced: its IDAT chunks (each CRC checked) inflated whole by
// libdeflate and unfiltered, into `samples` (width * channels bytes a row, no filter bytes). False
// where it cannot read them all (a chunk cut short, a CRC that does not match, a stream that ends
// before the rows or runs on past them, an undefined filter): libpng then reads the file, and its
// image or its error stands.
bool quickRows8(const unsigned char* data, std::size_t size, const PngHeader& header, int channels,
                std::vector<unsigned char>& samples);

}  // namespace artemis::io::detail
