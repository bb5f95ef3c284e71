// A stand-in for an ONNX Runtime older than ARTEMIS supports: its OrtGetApiBase hands out no API of
// the version asked for, and calls itself 1.2.3 (tests/cli/run_onnx_cli_test.cpp).
#include <cstdint>

namespace {
struct FakeApiBase {
  const void* (*get_api)(std::uint32_t);
  const char* (*version)();
};
const void* noApi(std::uint32_t /*version*/) {
  return nullptr;
}
const char* oldVersion() {
  return "1.2.3";
}
const FakeApiBase kBase{noApi, oldVersion};
}  // namespace

extern "C" __attribute__((visibility("default"))) const FakeApiBase* OrtGetApiBase() {
  return &kBase;
}
