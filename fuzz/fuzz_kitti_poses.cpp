// Trajectory files (poses/NN.txt, trajectory.txt, reference_poses.txt): readPoseFile.
#include <cmath>
#include <string>

#include "artemis/datasets/pose_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "00.txt");
  auto poses = datasets::readPoseFile(path);
  if (!poses) return artemis::fuzz::rejected(poses.status());
  // Accepted poses are rigid (the reader checks the rotation): their inverse is finite.
  for (const auto& T : *poses) {
    const Isometry3d inv = T.inverse();
    if (!inv.matrix().allFinite()) fuzz::invariantBroken("readPoseFile", "accepted a pose with a non-finite inverse");
  }
  return 0;
}
