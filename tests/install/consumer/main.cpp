#include <unistd.h>
#include <artemis/core/transform.hpp>
#include <artemis/io/png.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

// The io module links from the installed package with its own dependencies (libpng, libdeflate):
// a small picture written and read back.
bool pngRoundTrip() {
  artemis::ImageU8 image(3, 2, 3);
  image.at(2, 1, 0) = 200;
  const auto path =
      std::filesystem::temp_directory_path() / ("artemis_consumer_" + std::to_string(::getpid()) + ".png");
  if (!artemis::io::writePng(path, image).isOk()) return false;
  const auto read = artemis::io::readPng8(path, 3);
  std::filesystem::remove(path);
  return read.isOk() && read->at(2, 1, 0) == 200;
}

int main() {
  artemis::Isometry3d T = artemis::Isometry3d::Identity();
  T.translation() << 1.0, 2.0, 3.0;
  const auto back = artemis::isometryFromRowMajor3x4(artemis::toRowMajor3x4(T.inverse()));
  if (!back.isOk()) return 1;
  const double x = back->translation().x();
  std::printf("inverse translation x = %.1f\n", x);
  if (!pngRoundTrip()) return 1;
  std::printf("PNG written and read back\n");
  return x == -1.0 ? 0 : 1;
}
