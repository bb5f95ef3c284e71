// KITTI 3-D box labels: a tracking label_02 file or an object label file (the form is told by the
// first row; the file is named 000007.txt so that an object file has a frame): readKittiBoxes,
// then each box into the LiDAR frame.
#include <string>

#include "artemis/datasets/kitti_boxes.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "000007.txt");
  auto labels = datasets::readKittiBoxes(path);
  if (!labels) return artemis::fuzz::rejected(labels.status());
  for (std::size_t i = 1; i < labels->frames.size(); ++i) {
    if (labels->frames[i - 1] >= labels->frames[i]) {
      fuzz::invariantBroken("readKittiBoxes", "frames not sorted and unique");
    }
  }
  double sink = 0.0;
  for (const auto& box : labels->boxes) {
    sink += datasets::kittiBoxPoseInLidar(box, Isometry3d::Identity()).translation().sum();
  }
  return sink == 1.2345 ? 1 : 0;
}
