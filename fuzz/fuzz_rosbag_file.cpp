// A whole ROS 1 bag file, as a user hands one to `artemis dataset info` and `artemis run`: its
// index (Debian's rosbag_storage through rosbag_file.hpp), every message streamed in time order,
// and single messages read back by topic and time, as a run's frames are.
#include "artemis/datasets/rosbag_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "recording.bag");
  auto summary = datasets::readBagSummary(path);
  if (!summary) {
    fuzz::rejected(summary.status());
    return 0;
  }
  std::size_t messages = 0;
  std::string first_topic;
  std::int64_t first_ns = 0;
  const Status streamed = datasets::forEachBagMessage(path, {}, [&](const datasets::BagMessage& m) {
    if (messages++ == 0) {
      first_topic = m.topic;
      first_ns = m.stamp_ns;
    }
    return Status::ok();
  });
  if (!streamed.isOk()) {
    fuzz::rejected(streamed);
    return 0;
  }
  if (messages == 0) return 0;
  auto reader = datasets::BagReader::open(path);
  if (!reader) {
    fuzz::rejected(reader.status());
    return 0;
  }
  if (auto bytes = (*reader)->read(first_topic, first_ns); !bytes) fuzz::rejected(bytes.status());
  return 0;
}
