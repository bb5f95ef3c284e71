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

}  // namespace artemis::io::detail
