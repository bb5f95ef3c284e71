#pragma once
// The ONNX segmenter's test models: written by tests/semantics/write_onnx_models.py with Debian's
// python3-onnx into a test's folder, and run by the ONNX Runtime that scripts/install-deps.sh
// fetches. Where either is missing the test skips with the reason (fails under CI=true).

#include <cstdlib>
#include <filesystem>
#include <string>

#include "artemis/semantics/onnx_runtime.hpp"
#include "support/test_support.hpp"

namespace artemis::test {

// Writes the models into `dir`; false with the reason in `why` when they cannot be written or the
// runtime cannot be loaded.
inline bool writeOnnxModels(const std::filesystem::path& dir, std::string& why) {
  const std::string python = "/usr/bin/python3";
  if (std::system((python + " -c \"import onnx\" >/dev/null 2>&1").c_str()) != 0) {
    why = python + " cannot import onnx (install python3-onnx)";
    return false;
  }
  const std::string cmd =
      python + " " + (sourceDir() / "tests/semantics/write_onnx_models.py").string() + " " + dir.string();
  if (std::system(cmd.c_str()) != 0) {
    why = "the test model writer failed: " + cmd;
    return false;
  }
  auto runtime = semantics::onnx::runtimeInfo({});
  if (!runtime) {
    why = runtime.status().message();
    return false;
  }
  return true;
}

}  // namespace artemis::test

// Writes the test models into `dir`, or skips the test (fails it under CI=true).
#define ARTEMIS_REQUIRE_ONNX_MODELS(dir)                              \
  do {                                                                \
    std::string artemis_onnx_why;                                     \
    if (!::artemis::test::writeOnnxModels(dir, artemis_onnx_why)) {   \
      if (::artemis::test::runningInCi()) FAIL() << artemis_onnx_why; \
      GTEST_SKIP() << artemis_onnx_why;                               \
    }                                                                 \
  } while (false)
