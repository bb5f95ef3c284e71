// A run folder's config.json (written by `artemis run`, read back by the evaluators and the viewer):
// readRunRecording of apps/artemis/run_folder.cpp, compiled into this target (the CLI is no
// library), which also parses the frame range (FrameRange::parse).
#include "fuzz_common.hpp"
#include "run_folder.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "config.json");
  auto recording = cli::readRunRecording(path);
  if (!recording) return artemis::fuzz::rejected(recording.status());
  if (recording->frames.begin > recording->frames.end) {
    fuzz::invariantBroken("readRunRecording", "a frame range that ends before it begins");
  }
  // The range as text parses back to itself.
  auto again = datasets::FrameRange::parse(recording->frames.toString());
  if (!again || again->begin != recording->frames.begin || again->end != recording->frames.end) {
    fuzz::invariantBroken("FrameRange", "toString() does not parse back: " + recording->frames.toString());
  }
  return 0;
}
