// KITTI raw GPS/IMU packet (oxts/data/*.txt): readOxtsFile, then the devkit's conversion to poses
// that every packet of a drive goes through.
#include "artemis/datasets/oxts.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "0000000000.txt");
  auto packet = datasets::readOxtsFile(path);
  if (!packet) return artemis::fuzz::rejected(packet.status());
  // The packet first of a drive (it sets the Mercator scale) and second after a valid one.
  const datasets::OxtsPacket origin{49.0, 8.4, 112.0, 0.02, 0.01, 1.2};
  auto poses = datasets::oxtsToLidarPoses({*packet, origin}, Isometry3d::Identity());
  poses = datasets::oxtsToLidarPoses({origin, *packet}, Isometry3d::Identity());
  (void)poses;
  return 0;
}
