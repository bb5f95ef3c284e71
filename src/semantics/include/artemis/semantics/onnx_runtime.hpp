#pragma once
// ONNX Runtime, loaded when first asked for (dlopen) and never linked: a user without it builds and
// runs everything else, and one who has it (a CPU build, or a GPU build with its CUDA provider)
// brings their own. Only onnx_runtime.cpp sees the runtime's C API header.
//
// Where the library comes from, first found wins: RuntimeOptions::library; the environment
// variable ARTEMIS_ONNXRUNTIME_LIBRARY; the system's (libonnxruntime.so.1, libonnxruntime.so, as
// the dynamic loader finds them); the copy scripts/install-deps.sh fetched beside the build
// (third_party/onnxruntime/lib). A missing library, one that is not ONNX Runtime, and one older than
// kMinimumApiVersion are errors that say which file and what to do.
//
// Tensors cross the boundary as plain row-major arrays (float or int64); a Session names its
// inputs and outputs and their shapes (-1 for a dimension the model leaves open), so callers
// identify outputs by shape rather than by order.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::semantics::onnx {

// ONNX Runtime 1.16 (API 16) and later: the oldest whose C API has everything used here.
inline constexpr std::uint32_t kMinimumApiVersion = 16;

enum class ElementType { kFloat, kInt64, kInt32, kUint8, kOther };
const char* toString(ElementType type);

struct TensorInfo {
  std::string name;
  ElementType type = ElementType::kOther;
  std::vector<std::int64_t> shape;  // -1: left open by the model
};

// A CPU tensor, row-major: `values` for float tensors, `ints` for int64 ones.
struct Tensor {
  ElementType type = ElementType::kFloat;
  std::vector<std::int64_t> shape;
  std::vector<float> values;
  std::vector<std::int64_t> ints;
  [[nodiscard]] std::size_t elements() const;
};

struct RuntimeOptions {
  std::string library;            // empty: see above
  std::string provider = "auto";  // "cpu", "cuda" (required), "auto" (CUDA when the runtime has it)
  int threads = 0;                // intra-op threads; 0: the runtime's choice
};

class Runtime;

class Session {
 public:
  // Loads the runtime (once per process) and the model file or bytes: an unreadable or corrupt
  // model, or a provider that cannot be had, is an error naming the model.
  static Result<std::unique_ptr<Session>> open(const std::filesystem::path& model, const RuntimeOptions& options);
  static Result<std::unique_ptr<Session>> fromBytes(std::span<const std::byte> model, const std::string& name,
                                                    const RuntimeOptions& options);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  [[nodiscard]] const std::vector<TensorInfo>& inputs() const;
  [[nodiscard]] const std::vector<TensorInfo>& outputs() const;
  [[nodiscard]] const std::string& name() const;      // the model's file, for messages
  [[nodiscard]] const std::string& provider() const;  // "cpu" or "cuda"
  // The input or output named `name`, or nullptr.
  [[nodiscard]] const TensorInfo* input(const std::string& name) const;

  // Runs the model on `feeds` (one tensor per input, in inputs() order, shapes within the
  // model's); returns every output, in outputs() order, as float tensors (integer outputs
  // converted). Errors name the model and say what the runtime said.
  Result<std::vector<Tensor>> run(std::span<const Tensor> feeds);

 private:
  struct Impl;
  explicit Session(std::unique_ptr<Impl> impl);
  // From a file (`path`) or from bytes (`model`, path empty).
  static Result<std::unique_ptr<Session>> create(const std::string& path, std::span<const std::byte> model,
                                                 const std::string& name, const RuntimeOptions& options);
  std::unique_ptr<Impl> impl_;
};

// The runtime the process loaded (or would load with `options`): its file and version, and whether
// it has the CUDA provider. An error when it cannot be loaded, as for Session::open.
struct RuntimeInfo {
  std::string library;
  std::string version;
  bool cuda = false;
};
Result<RuntimeInfo> runtimeInfo(const RuntimeOptions& options);

}  // namespace artemis::semantics::onnx
