#pragma once
// PNG files put together chunk by chunk, for the tests that need what no writer makes.

#include <zlib.h>

#include <cstdint>
#include <string>

namespace artemis::io::test_png {

inline void appendBigEndian(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((value >> shift) & 0xFF));
}

// A chunk: its length, type, data and CRC.
inline void appendChunk(std::string& out, const std::string& type, const std::string& data) {
  appendBigEndian(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  out += body;
  appendBigEndian(out, static_cast<std::uint32_t>(
                           crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
}

// `raw` as one zlib stream (what a PNG's IDAT chunks hold), empty if zlib fails.
inline std::string zlibStream(const std::string& raw) {
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string stream(size, '\0');
  if (compress(reinterpret_cast<Bytef*>(stream.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
               static_cast<uLong>(raw.size())) != Z_OK) {
    return {};
  }
  stream.resize(size);
  return stream;
}

// The signature and an IHDR chunk: 8-bit samples of `colour_type`, not interlaced.
inline std::string pngStart(std::uint32_t width, std::uint32_t height, int colour_type) {
  std::string file("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  appendBigEndian(ihdr, width);
  appendBigEndian(ihdr, height);
  ihdr += std::string{'\x08', static_cast<char>(colour_type), '\0', '\0', '\0'};
  appendChunk(file, "IHDR", ihdr);
  return file;
}

}  // namespace artemis::io::test_png
