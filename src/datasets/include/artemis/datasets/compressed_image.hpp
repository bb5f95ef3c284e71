#pragma once
// Decoding of the JPEG and PNG pictures that sensor_msgs/CompressedImage carries, from memory, as
// RGB (stb_image, inside compressed_image.cpp only). The size is read from the header first: a
// picture over 2^26 pixels is refused before any pixel memory is allocated.

#include <cstdint>
#include <span>
#include <string>

#include "artemis/core/image.hpp"
#include "artemis/core/status.hpp"

namespace artemis::datasets {

// `what` names the picture in errors (e.g. "bag.bag: /camera/image_raw/compressed message 12").
Result<ImageU8> decodeCompressedPicture(std::span<const std::uint8_t> bytes, const std::string& what);

}  // namespace artemis::datasets
