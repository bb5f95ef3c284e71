// PNG (camera images, mask ids, depth, label images): readPng8 (as stored and converted to RGB)
// and readPng16.
#include "artemis/io/png.hpp"
#include "fuzz_common.hpp"

namespace {

template <typename Image>
void checkImage(const Image& image, int channels_wanted, const char* what) {
  const auto expected = static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(image.height()) *
                        static_cast<std::size_t>(image.channels());
  if (image.width() <= 0 || image.height() <= 0 || image.data().size() != expected ||
      (channels_wanted != 0 && image.channels() != channels_wanted)) {
    artemis::fuzz::invariantBroken(what, "image size, channels and pixel count disagree");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "000000.png");
  if (auto image = io::readPng8(path); image) {
    checkImage(*image, 0, "readPng8");
  } else {
    fuzz::rejected(image.status());
  }
  if (auto image = io::readPng8(path, 3); image) {
    checkImage(*image, 3, "readPng8(3)");
  } else {
    fuzz::rejected(image.status());
  }
  if (auto image = io::readPng16(path); image) {
    checkImage(*image, 1, "readPng16");
  } else {
    fuzz::rejected(image.status());
  }
  return 0;
}
