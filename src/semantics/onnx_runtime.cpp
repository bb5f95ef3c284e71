// ONNX Runtime through its C API, loaded with dlopen (onnx_runtime.hpp). The runtime's header is
// seen here only; a build without it (scripts/install-deps.sh fetches it) still compiles, and every
// call says how to get it.
#include "artemis/semantics/onnx_runtime.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <numeric>
#include <optional>

#include "artemis/io/read_file.hpp"

#ifdef ARTEMIS_HAVE_ONNXRUNTIME_HEADERS
#include <onnxruntime_c_api.h>
#endif

namespace artemis::semantics::onnx {

const char* toString(ElementType type) {
  switch (type) {
    case ElementType::kFloat: return "float";
    case ElementType::kInt64: return "int64";
    case ElementType::kInt32: return "int32";
    case ElementType::kUint8: return "uint8";
    case ElementType::kOther: break;
  }
  return "another type";
}

std::size_t Tensor::elements() const {
  return std::accumulate(shape.begin(), shape.end(), std::size_t{1}, [](std::size_t n, std::int64_t d) {
    return n * static_cast<std::size_t>(std::max<std::int64_t>(d, 0));
  });
}

namespace {

std::string shapeText(const std::vector<std::int64_t>& shape) {
  std::string out = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    out += (i > 0 ? ", " : "") + (shape[i] < 0 ? std::string("?") : std::to_string(shape[i]));
  }
  return out + "]";
}

// The library candidates, in order, and whether the first one is the user's explicit choice.
std::vector<std::string> libraryCandidates(const RuntimeOptions& options, bool& chosen) {
  chosen = true;
  if (!options.library.empty()) return {options.library};
  if (const char* env = std::getenv("ARTEMIS_ONNXRUNTIME_LIBRARY"); env != nullptr && *env != '\0') return {env};
  chosen = false;
  std::vector<std::string> out{"libonnxruntime.so.1", "libonnxruntime.so"};
#ifdef ARTEMIS_ONNXRUNTIME_DEFAULT_LIBRARY
  out.emplace_back(ARTEMIS_ONNXRUNTIME_DEFAULT_LIBRARY);
#endif
  return out;
}

}  // namespace

#ifndef ARTEMIS_HAVE_ONNXRUNTIME_HEADERS

namespace {
Status noHeaders() {
  return notFound(
      "this build of ARTEMIS has no ONNX Runtime headers: run scripts/install-deps.sh (it fetches them into "
      "third_party/onnxruntime) and build again");
}
}  // namespace

struct Session::Impl {
  std::vector<TensorInfo> inputs, outputs;
  std::string name, provider;
};
Session::Session(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Session::~Session() = default;
Result<std::unique_ptr<Session>> Session::open(const std::filesystem::path&, const RuntimeOptions&) {
  return noHeaders();
}
Result<std::unique_ptr<Session>> Session::fromBytes(std::span<const std::byte>, const std::string&,
                                                    const RuntimeOptions&) {
  return noHeaders();
}
Result<std::vector<Tensor>> Session::run(std::span<const Tensor>) {
  return noHeaders();
}
Result<RuntimeInfo> runtimeInfo(const RuntimeOptions&) {
  return noHeaders();
}

#else

namespace {

// The loaded runtime: one per process (ONNX Runtime keeps global state; it is never unloaded).
struct Loaded {
  void* handle = nullptr;
  const OrtApi* api = nullptr;
  OrtEnv* env = nullptr;
  RuntimeInfo info;
};

// An OrtStatus as a Status (released); ok for nullptr.
Status statusOf(const OrtApi* api, OrtStatus* s, const std::string& what) {
  if (s == nullptr) return Status::ok();
  std::string message = fmt::format("{}: {}", what, api->GetErrorMessage(s));
  api->ReleaseStatus(s);
  return ioError(std::move(message));
}

// Releases the status of a call whose failure leaves a usable default (the value stays as set).
void drop(const OrtApi* api, OrtStatus* s) {
  if (s != nullptr) api->ReleaseStatus(s);
}

// Opens one candidate; an error says why it is not a usable runtime.
Result<Loaded> openLibrary(const std::string& path) {
  dlerror();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    return notFound(fmt::format("{}: {}", path, why != nullptr ? why : "cannot be loaded"));
  }
  using GetApiBase = const OrtApiBase* (*)();
  auto get_base = reinterpret_cast<GetApiBase>(dlsym(handle, "OrtGetApiBase"));
  const OrtApiBase* base = get_base != nullptr ? get_base() : nullptr;
  if (base == nullptr) {
    dlclose(handle);
    return invalidArgument(fmt::format("{}: not ONNX Runtime (no OrtGetApiBase)", path));
  }
  Loaded loaded;
  loaded.handle = handle;
  loaded.info.version = base->GetVersionString != nullptr ? base->GetVersionString() : "unknown";
  loaded.api = base->GetApi(kMinimumApiVersion);
  if (loaded.api == nullptr) {
    dlclose(handle);
    return invalidArgument(
        fmt::format("{}: ONNX Runtime {} is too old: ARTEMIS needs 1.{} or later (C API {}); use a newer runtime "
                    "(--model-config's runtime.library, ARTEMIS_ONNXRUNTIME_LIBRARY)",
                    path, loaded.info.version, kMinimumApiVersion, kMinimumApiVersion));
  }
  Dl_info where{};
  loaded.info.library =
      dladdr(reinterpret_cast<void*>(get_base), &where) != 0 && where.dli_fname != nullptr ? where.dli_fname : path;
  char** providers = nullptr;
  int count = 0;
  if (OrtStatus* listed = loaded.api->GetAvailableProviders(&providers, &count); listed == nullptr) {
    for (int i = 0; i < count; ++i) loaded.info.cuda |= std::string(providers[i]) == "CUDAExecutionProvider";
    drop(loaded.api, loaded.api->ReleaseAvailableProviders(providers, count));
  } else {
    drop(loaded.api, listed);
  }
  if (Status st = statusOf(loaded.api, loaded.api->CreateEnv(ORT_LOGGING_LEVEL_ERROR, "artemis", &loaded.env),
                           path + ": creating the runtime's environment");
      !st.isOk()) {
    dlclose(handle);
    return st;
  }
  return loaded;
}

std::mutex& loadMutex() {
  static std::mutex m;
  return m;
}

// The process's runtime, loaded on first use.
Result<const Loaded*> runtime(const RuntimeOptions& options) {
  static std::optional<Loaded> loaded;
  std::lock_guard lock(loadMutex());
  bool chosen = false;
  const std::vector<std::string> candidates = libraryCandidates(options, chosen);
  if (loaded) {
    // One runtime per process: a second, different one cannot be loaded beside it.
    void* same = chosen ? dlopen(candidates.front().c_str(), RTLD_NOW | RTLD_NOLOAD) : loaded->handle;
    if (same != nullptr && same != loaded->handle) dlclose(same);
    if (same != loaded->handle) {
      return invalidArgument(fmt::format("{}: another ONNX Runtime ({}) is loaded already in this process",
                                         candidates.front(), loaded->info.library));
    }
    if (chosen) dlclose(same);  // the reference RTLD_NOLOAD took
    return &*loaded;
  }
  std::string tried;
  for (const std::string& path : candidates) {
    auto one = openLibrary(path);
    if (one) {
      loaded = std::move(*one);
      return &*loaded;
    }
    if (chosen || one.status().code() != StatusCode::kNotFound) return one.status();
    tried += "\n  " + one.status().message();
  }
  return notFound(
      "ONNX Runtime not found; tried:" + tried +
      "\nRun scripts/install-deps.sh (it fetches the CPU build into third_party/onnxruntime), install it system-wide, "
      "or name the library with ARTEMIS_ONNXRUNTIME_LIBRARY or the model config's runtime.library");
}

ElementType elementType(ONNXTensorElementDataType t) {
  switch (t) {
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_FLOAT: return ElementType::kFloat;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT64: return ElementType::kInt64;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT32: return ElementType::kInt32;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_UINT8: return ElementType::kUint8;
    default: return ElementType::kOther;
  }
}

}  // namespace

struct Session::Impl {
  const Loaded* rt = nullptr;
  OrtSession* session = nullptr;
  OrtMemoryInfo* memory = nullptr;
  std::vector<TensorInfo> inputs, outputs;
  std::string name, provider = "cpu";
  ~Impl() {
    if (rt == nullptr) return;
    if (memory != nullptr) rt->api->ReleaseMemoryInfo(memory);
    if (session != nullptr) rt->api->ReleaseSession(session);
  }
  Status check(OrtStatus* s, const std::string& what) const { return statusOf(rt->api, s, name + ": " + what); }
  // The names, element types and shapes of the inputs (or outputs).
  Result<std::vector<TensorInfo>> describe(bool outputs_side) const;
};

Result<std::vector<TensorInfo>> Session::Impl::describe(bool outputs_side) const {
  const OrtApi* api = rt->api;
  std::size_t count = 0;
  if (Status st =
          check(outputs_side ? api->SessionGetOutputCount(session, &count) : api->SessionGetInputCount(session, &count),
                "counting its inputs and outputs");
      !st.isOk()) {
    return st;
  }
  OrtAllocator* allocator = nullptr;
  if (Status st = check(api->GetAllocatorWithDefaultOptions(&allocator), "allocator"); !st.isOk()) return st;
  std::vector<TensorInfo> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    char* name_c = nullptr;
    if (Status st = check(outputs_side ? api->SessionGetOutputName(session, i, allocator, &name_c)
                                       : api->SessionGetInputName(session, i, allocator, &name_c),
                          "reading a tensor's name");
        !st.isOk()) {
      return st;
    }
    out[i].name = name_c;
    drop(api, api->AllocatorFree(allocator, name_c));
    OrtTypeInfo* type_info = nullptr;
    if (Status st = check(outputs_side ? api->SessionGetOutputTypeInfo(session, i, &type_info)
                                       : api->SessionGetInputTypeInfo(session, i, &type_info),
                          "reading " + out[i].name + "'s type");
        !st.isOk()) {
      return st;
    }
    const OrtTensorTypeAndShapeInfo* tensor = nullptr;
    if (OrtStatus* cast = api->CastTypeInfoToTensorInfo(type_info, &tensor); cast != nullptr) {
      drop(api, cast);  // not a tensor (a map, a sequence): its type stays kOther
      tensor = nullptr;
    }
    if (tensor != nullptr) {
      ONNXTensorElementDataType element{};
      std::size_t rank = 0;
      drop(api, api->GetTensorElementType(tensor, &element));
      drop(api, api->GetDimensionsCount(tensor, &rank));
      out[i].type = elementType(element);
      out[i].shape.resize(rank);
      drop(api, api->GetDimensions(tensor, out[i].shape.data(), rank));
      for (auto& d : out[i].shape) d = d > 0 ? d : -1;
    }
    api->ReleaseTypeInfo(type_info);
  }
  return out;
}

Session::Session(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Session::~Session() = default;

Result<std::unique_ptr<Session>> Session::open(const std::filesystem::path& model, const RuntimeOptions& options) {
  // The runtime reads the file itself (a model may keep its weights in files beside it); it is
  // checked first, so that a missing file, a folder or a FIFO is an error naming it.
  if (auto size = io::checkInputFile(model, io::limits::kModel); !size) return size.status();
  return create(model.string(), {}, model.string(), options);
}

Result<std::unique_ptr<Session>> Session::fromBytes(std::span<const std::byte> model, const std::string& name,
                                                    const RuntimeOptions& options) {
  return create({}, model, name, options);
}

Result<std::unique_ptr<Session>> Session::create(const std::string& path, std::span<const std::byte> model,
                                                 const std::string& name, const RuntimeOptions& options) {
  if (options.provider != "cpu" && options.provider != "cuda" && options.provider != "auto") {
    return invalidArgument(fmt::format("{}: provider '{}' is none of cpu, cuda, auto", name, options.provider));
  }
  auto rt = runtime(options);
  if (!rt) return rt.status();
  auto impl = std::make_unique<Impl>();
  impl->rt = *rt;
  impl->name = name;
  const OrtApi* api = impl->rt->api;
  OrtSessionOptions* settings = nullptr;
  if (Status st = impl->check(api->CreateSessionOptions(&settings), "session options"); !st.isOk()) return st;
  const auto release_settings = [&] { api->ReleaseSessionOptions(settings); };
  if (options.threads > 0) drop(api, api->SetIntraOpNumThreads(settings, options.threads));
  drop(api, api->SetSessionGraphOptimizationLevel(settings, ORT_ENABLE_ALL));
  if (options.provider != "cpu") {
    const bool cuda = impl->rt->info.cuda;
    Status added = Status::ok();
    if (cuda) {
      OrtCUDAProviderOptions cuda_options;
      added =
          impl->check(api->SessionOptionsAppendExecutionProvider_CUDA(settings, &cuda_options), "the CUDA provider");
    }
    if (options.provider == "cuda" && (!cuda || !added.isOk())) {
      release_settings();
      return invalidArgument(!cuda ? fmt::format("{}: provider cuda, but ONNX Runtime {} ({}) has no CUDA provider: "
                                                 "use a GPU build of ONNX Runtime, or provider cpu",
                                                 name, impl->rt->info.version, impl->rt->info.library)
                                   : added.message());
    }
    if (cuda && added.isOk()) impl->provider = "cuda";
  }
  const Status created = impl->check(
      path.empty() ? api->CreateSessionFromArray(impl->rt->env, model.data(), model.size(), settings, &impl->session)
                   : api->CreateSession(impl->rt->env, path.c_str(), settings, &impl->session),
      "not a model ONNX Runtime can load");
  release_settings();
  if (!created.isOk()) return created;
  if (Status st =
          impl->check(api->CreateCpuMemoryInfo(OrtArenaAllocator, OrtMemTypeDefault, &impl->memory), "CPU memory info");
      !st.isOk()) {
    return st;
  }
  auto inputs = impl->describe(false);
  if (!inputs) return inputs.status();
  auto outputs = impl->describe(true);
  if (!outputs) return outputs.status();
  impl->inputs = std::move(*inputs);
  impl->outputs = std::move(*outputs);
  return std::unique_ptr<Session>(new Session(std::move(impl)));
}

namespace {

// Checks a feed against the model's input; the error names both.
Status checkFeed(const std::string& model, const TensorInfo& info, const Tensor& feed) {
  const bool type_ok = (info.type == ElementType::kFloat && feed.type == ElementType::kFloat) ||
                       (info.type == ElementType::kInt64 && feed.type == ElementType::kInt64);
  bool shape_ok = info.shape.size() == feed.shape.size();
  for (std::size_t i = 0; shape_ok && i < info.shape.size(); ++i) {
    shape_ok = feed.shape[i] > 0 && (info.shape[i] < 0 || info.shape[i] == feed.shape[i]);
  }
  const std::size_t have = feed.type == ElementType::kFloat ? feed.values.size() : feed.ints.size();
  if (!type_ok || !shape_ok || have != feed.elements()) {
    return invalidArgument(fmt::format("{}: input '{}' takes {} {}, given {} {} ({} values)", model, info.name,
                                       toString(info.type), shapeText(info.shape), toString(feed.type),
                                       shapeText(feed.shape), have));
  }
  return Status::ok();
}

// An output value as a float tensor.
Result<Tensor> tensorOf(const OrtApi* api, OrtValue* value, const std::string& what) {
  OrtTensorTypeAndShapeInfo* info = nullptr;
  if (Status st = statusOf(api, api->GetTensorTypeAndShape(value, &info), what); !st.isOk()) return st;
  ONNXTensorElementDataType element{};
  std::size_t rank = 0;
  drop(api, api->GetTensorElementType(info, &element));
  drop(api, api->GetDimensionsCount(info, &rank));
  Tensor out;
  out.shape.resize(rank);
  drop(api, api->GetDimensions(info, out.shape.data(), rank));
  api->ReleaseTensorTypeAndShapeInfo(info);
  void* data = nullptr;
  if (Status st = statusOf(api, api->GetTensorMutableData(value, &data), what); !st.isOk()) return st;
  const std::size_t n = out.elements();
  out.values.resize(n);
  switch (elementType(element)) {
    case ElementType::kFloat: std::copy_n(static_cast<const float*>(data), n, out.values.begin()); break;
    case ElementType::kInt64:
      std::transform(static_cast<const std::int64_t*>(data), static_cast<const std::int64_t*>(data) + n,
                     out.values.begin(), [](std::int64_t x) { return static_cast<float>(x); });
      break;
    case ElementType::kInt32:
      std::transform(static_cast<const std::int32_t*>(data), static_cast<const std::int32_t*>(data) + n,
                     out.values.begin(), [](std::int32_t x) { return static_cast<float>(x); });
      break;
    case ElementType::kUint8:
      std::transform(static_cast<const std::uint8_t*>(data), static_cast<const std::uint8_t*>(data) + n,
                     out.values.begin(), [](std::uint8_t x) { return static_cast<float>(x); });
      break;
    case ElementType::kOther: return invalidArgument(what + ": an output of a type other than float or integer");
  }
  return out;
}

}  // namespace

Result<std::vector<Tensor>> Session::run(std::span<const Tensor> feeds) {
  const Impl& s = *impl_;
  const OrtApi* api = s.rt->api;
  if (feeds.size() != s.inputs.size()) {
    return invalidArgument(
        fmt::format("{}: the model takes {} inputs, given {}", s.name, s.inputs.size(), feeds.size()));
  }
  std::vector<OrtValue*> values(feeds.size(), nullptr);
  std::vector<OrtValue*> results(s.outputs.size(), nullptr);
  const auto release = [&] {
    for (OrtValue* v : values) {
      if (v != nullptr) api->ReleaseValue(v);
    }
    for (OrtValue* v : results) {
      if (v != nullptr) api->ReleaseValue(v);
    }
  };
  std::vector<const char*> input_names, output_names;
  for (std::size_t i = 0; i < feeds.size(); ++i) {
    const Tensor& feed = feeds[i];
    if (Status st = checkFeed(s.name, s.inputs[i], feed); !st.isOk()) {
      release();
      return st;
    }
    const bool floats = feed.type == ElementType::kFloat;
    void* data = floats ? static_cast<void*>(const_cast<float*>(feed.values.data()))
                        : static_cast<void*>(const_cast<std::int64_t*>(feed.ints.data()));
    const std::size_t bytes = feed.elements() * (floats ? sizeof(float) : sizeof(std::int64_t));
    if (Status st =
            s.check(api->CreateTensorWithDataAsOrtValue(
                        s.memory, data, bytes, feed.shape.data(), feed.shape.size(),
                        floats ? ONNX_TENSOR_ELEMENT_DATA_TYPE_FLOAT : ONNX_TENSOR_ELEMENT_DATA_TYPE_INT64, &values[i]),
                    "input '" + s.inputs[i].name + "'");
        !st.isOk()) {
      release();
      return st;
    }
    input_names.push_back(s.inputs[i].name.c_str());
  }
  for (const TensorInfo& o : s.outputs) output_names.push_back(o.name.c_str());
  if (Status st = s.check(api->Run(s.session, nullptr, input_names.data(), values.data(), values.size(),
                                   output_names.data(), output_names.size(), results.data()),
                          "running the model");
      !st.isOk()) {
    release();
    return st;
  }
  std::vector<Tensor> out;
  for (std::size_t i = 0; i < results.size(); ++i) {
    auto t = tensorOf(api, results[i], s.name + ": output '" + s.outputs[i].name + "'");
    if (!t) {
      release();
      return t.status();
    }
    out.push_back(std::move(*t));
  }
  release();
  return out;
}

Result<RuntimeInfo> runtimeInfo(const RuntimeOptions& options) {
  auto rt = runtime(options);
  if (!rt) return rt.status();
  return (*rt)->info;
}

#endif  // ARTEMIS_HAVE_ONNXRUNTIME_HEADERS

// Both builds' Impl hold the model's name, provider and tensors.
const std::vector<TensorInfo>& Session::inputs() const {
  return impl_->inputs;
}
const std::vector<TensorInfo>& Session::outputs() const {
  return impl_->outputs;
}
const std::string& Session::name() const {
  return impl_->name;
}
const std::string& Session::provider() const {
  return impl_->provider;
}

const TensorInfo* Session::input(const std::string& name) const {
  for (const TensorInfo& t : impl_->inputs) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

}  // namespace artemis::semantics::onnx
