// Timestamp files: KITTI raw's timestamps*.txt (date and time) and KITTI odometry's times.txt
// (seconds): readTimestampFile.
#include "artemis/datasets/kitti_files.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = artemis::fuzz::writeInput(data, size, "timestamps.txt");
  auto stamps = artemis::datasets::readTimestampFile(path);
  if (!stamps) return artemis::fuzz::rejected(stamps.status());
  return 0;
}
