// KITTI Velodyne scan (velodyne_points/data/*.bin, sequences/NN/velodyne/*.bin): readVelodyneBin.
#include <cmath>

#include "artemis/datasets/kitti_files.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "0000000000.bin");
  auto cloud = datasets::readVelodyneBin(path);
  if (!cloud) return artemis::fuzz::rejected(cloud.status());
  // The contract: 16 bytes a point, never an empty scan, one intensity a point.
  if (cloud->points.empty() || cloud->points.size() * 16 != size || cloud->intensity.size() != cloud->points.size()) {
    fuzz::invariantBroken("readVelodyneBin", "point count does not match the file size");
  }
  return 0;
}
