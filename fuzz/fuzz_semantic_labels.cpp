// SemanticKITTI label file (sequences/NN/labels/*.label): readLabelFile and the class table lookups
// a label goes through.
#include "artemis/datasets/kitti_files.hpp"
#include "artemis/datasets/semantic_kitti.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis::datasets;
  const auto path = artemis::fuzz::writeInput(data, size, "000000.label");
  // The scan beside it has as many points as the file has labels (the usual case), and one more
  // (a mismatch, which must be an error).
  const std::size_t points = size / 4;
  auto labels = readLabelFile(path, points);
  if (auto wrong = readLabelFile(path, points + 1); wrong.isOk()) {
    artemis::fuzz::invariantBroken("readLabelFile", "accepted a label count that differs from the scan's");
  }
  if (!labels) return artemis::fuzz::rejected(labels.status());
  if (labels->size() != points) artemis::fuzz::invariantBroken("readLabelFile", "wrong label count");
  std::size_t sink = 0;
  for (std::uint32_t label : *labels) {
    const std::uint16_t cls = semantic_kitti::classOf(label);
    const std::uint8_t train = semantic_kitti::toTrainId(cls);
    if (train > semantic_kitti::kNumTrainClasses) {
      artemis::fuzz::invariantBroken("toTrainId", "train id above kNumTrainClasses");
    }
    sink += semantic_kitti::trainName(train).size() + semantic_kitti::trainToRawId(train) +
            (semantic_kitti::find(cls) ? 1u : 0u) + semantic_kitti::instanceOf(label);
  }
  return sink == 0xFFFFFFFFu ? 1 : 0;  // keeps the lookups from being optimised away
}
