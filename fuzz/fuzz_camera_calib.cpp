// The camera calibration file of bag runs (--calib FILE, YAML key: value lines).
#include "artemis/datasets/camera_calib_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "camera.yaml");
  if (auto calib = datasets::readCameraCalibFile(path); calib) {
    if (calib->info.width <= 0 || calib->info.height <= 0 || !calib->T_L_C.matrix().allFinite()) {
      fuzz::invariantBroken("readCameraCalibFile", "an accepted file with a bad size or pose");
    }
  } else {
    fuzz::rejected(calib.status());
  }
  return 0;
}
