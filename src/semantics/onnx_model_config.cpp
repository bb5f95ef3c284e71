#include "artemis/semantics/onnx_model_config.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "artemis/io/read_file.hpp"

namespace artemis::semantics {

namespace {

using Json = nlohmann::json;

// Reads the JSON's values into a config, naming the file and key in every error.
class Reader {
 public:
  explicit Reader(std::string origin) : origin_(std::move(origin)) {}

  Status fail(const std::string& what) const { return parseError(origin_ + ": " + what); }

  // A number in [min, max] at key of j (absent: `value` stays).
  Status number(const Json& j, const char* key, const std::string& where, double min, double max, double& value) const {
    if (!j.contains(key)) return Status::ok();
    const Json& v = j[key];
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < min || v.get<double>() > max) {
      return fail(fmt::format("{}.{} must be a number in {}..{}, not {}", where, key, min, max, v.dump()));
    }
    value = v.get<double>();
    return Status::ok();
  }
  Status whole(const Json& j, const char* key, const std::string& where, std::int64_t min, std::int64_t max,
               std::int64_t& value) const {
    if (!j.contains(key)) return Status::ok();
    const Json& v = j[key];
    if (!v.is_number_integer() || v.get<std::int64_t>() < min || v.get<std::int64_t>() > max) {
      return fail(fmt::format("{}.{} must be a whole number in {}..{}, not {}", where, key, min, max, v.dump()));
    }
    value = v.get<std::int64_t>();
    return Status::ok();
  }
  Status text(const Json& j, const char* key, const std::string& where, std::string& value) const {
    if (!j.contains(key)) return Status::ok();
    if (!j[key].is_string()) return fail(fmt::format("{}.{} must be a string", where, key));
    value = j[key].get<std::string>();
    return Status::ok();
  }
  Status triple(const Json& j, const char* key, const std::string& where, std::array<double, 3>& value) const {
    if (!j.contains(key)) return Status::ok();
    const Json& v = j[key];
    if (!v.is_array() || v.size() != 3 || !std::all_of(v.begin(), v.end(), [](const Json& x) {
          return x.is_number() && std::isfinite(x.get<double>());
        })) {
      return fail(fmt::format("{}.{} must hold 3 numbers", where, key));
    }
    for (std::size_t c = 0; c < 3; ++c) value[c] = v[c].get<double>();
    return Status::ok();
  }
  Status input(const Json& j, const std::string& where, NetworkInput& in) const;
  Status instances(const Json& j, const Vocabulary& vocabulary, const std::filesystem::path& folder,
                   InstanceModelConfig& out) const;
  Status clip(const Json& j, const std::filesystem::path& folder, ClipConfig& out) const;
  Status runtime(const Json& j, onnx::RuntimeOptions& out) const;

 private:
  std::string origin_;
};

#define ARTEMIS_TRY(expr)                 \
  if (Status st_ = (expr); !st_.isOk()) { \
    return st_;                           \
  }

Status Reader::input(const Json& j, const std::string& where, NetworkInput& in) const {
  if (!j.is_object()) return fail(where + " must be an object");
  ARTEMIS_TRY(text(j, "name", where, in.name));
  if (j.contains("size")) {
    const Json& s = j["size"];
    if (!s.is_array() || s.size() != 2 || !s[0].is_number_integer() || !s[1].is_number_integer() ||
        s[0].get<std::int64_t>() < 8 || s[0].get<std::int64_t>() > 8192 || s[1].get<std::int64_t>() < 8 ||
        s[1].get<std::int64_t>() > 8192) {
      return fail(where + ".size must be [width, height], each 8..8192");
    }
    in.width = static_cast<int>(s[0].get<std::int64_t>());
    in.height = static_cast<int>(s[1].get<std::int64_t>());
  }
  if (j.contains("letterbox")) {
    if (!j["letterbox"].is_boolean()) return fail(where + ".letterbox must be true or false");
    in.letterbox = j["letterbox"].get<bool>();
  }
  std::int64_t pad = in.pad_value;
  ARTEMIS_TRY(whole(j, "pad_value", where, 0, 255, pad));
  in.pad_value = static_cast<int>(pad);
  ARTEMIS_TRY(number(j, "scale", where, -1e6, 1e6, in.scale));
  if (in.scale == 0.0) return fail(where + ".scale must not be 0");
  ARTEMIS_TRY(triple(j, "mean", where, in.mean));
  ARTEMIS_TRY(triple(j, "std", where, in.std));
  if (std::any_of(in.std.begin(), in.std.end(), [](double s) { return s == 0.0; })) {
    return fail(where + ".std must not hold 0");
  }
  std::string order = in.bgr ? "bgr" : "rgb";
  ARTEMIS_TRY(text(j, "channel_order", where, order));
  if (order != "rgb" && order != "bgr")
    return fail(fmt::format("{}.channel_order is '{}', not rgb or bgr", where, order));
  in.bgr = order == "bgr";
  std::string interpolation = in.nearest ? "nearest" : "linear";
  ARTEMIS_TRY(text(j, "interpolation", where, interpolation));
  if (interpolation != "linear" && interpolation != "nearest") {
    return fail(fmt::format("{}.interpolation is '{}', not linear or nearest", where, interpolation));
  }
  in.nearest = interpolation == "nearest";
  return Status::ok();
}

Status Reader::instances(const Json& j, const Vocabulary& vocabulary, const std::filesystem::path& folder,
                         InstanceModelConfig& out) const {
  if (!j.is_object()) return fail("\"instances\" must be an object");
  std::string model;
  ARTEMIS_TRY(text(j, "model", "instances", model));
  if (model.empty()) return fail("instances.model (the ONNX file) is missing");
  out.model = folder / model;
  if (j.contains("input")) ARTEMIS_TRY(input(j["input"], "instances.input", out.input));
  double score = out.detection.score_threshold;
  double iou = out.detection.iou_threshold;
  double mask = out.mask_threshold;
  ARTEMIS_TRY(number(j, "score_threshold", "instances", 0.0, 1.0, score));
  ARTEMIS_TRY(number(j, "iou_threshold", "instances", 0.0, 1.0, iou));
  ARTEMIS_TRY(number(j, "mask_threshold", "instances", 0.001, 0.999, mask));
  std::int64_t max = static_cast<std::int64_t>(out.detection.max_detections);
  ARTEMIS_TRY(whole(j, "max_detections", "instances", 1, 1000, max));
  out.detection = {static_cast<float>(score), static_cast<float>(iou), static_cast<std::size_t>(max)};
  out.mask_threshold = static_cast<float>(mask);
  std::string layout = "auto";
  ARTEMIS_TRY(text(j, "layout", "instances", layout));
  if (!parseLayout(layout, out.layout)) {
    return fail(fmt::format("instances.layout is '{}', not auto, dense, dense_transposed or end_to_end", layout));
  }
  if (!j.contains("labels") || !j["labels"].is_array() || j["labels"].empty() || j["labels"].size() > 100000 ||
      !std::all_of(j["labels"].begin(), j["labels"].end(), [](const Json& l) { return l.is_string(); })) {
    return fail("instances.labels must list the network's classes (strings), in its order");
  }
  for (const Json& l : j["labels"]) out.labels.push_back(l.get<std::string>());
  out.label_classes.assign(out.labels.size(), kNoClass);
  if (!j.contains("classes")) return Status::ok();
  if (!j["classes"].is_object()) return fail("instances.classes must map labels to classes (or null)");
  for (const auto& [label, cls] : j["classes"].items()) {
    const auto at = std::find(out.labels.begin(), out.labels.end(), label);
    if (at == out.labels.end()) return fail(fmt::format("instances.classes maps '{}', which is not in labels", label));
    if (cls.is_null()) continue;
    if (!cls.is_string()) return fail(fmt::format("instances.classes['{}'] must be a class name or null", label));
    const SemanticClass* c = vocabulary.findByName(cls.get<std::string>());
    if (c == nullptr) {
      return fail(fmt::format("instances.classes maps '{}' to '{}', which is not a class of the vocabulary", label,
                              cls.get<std::string>()));
    }
    out.label_classes[static_cast<std::size_t>(at - out.labels.begin())] = c->id;
  }
  return Status::ok();
}

Status Reader::clip(const Json& j, const std::filesystem::path& folder, ClipConfig& out) const {
  if (!j.is_object()) return fail("\"clip\" must be an object");
  // CLIP's own preprocessing: 224 x 224, its channel means and deviations, the image stretched
  // (the crop is made square first).
  out.image_input.width = out.image_input.height = 224;
  out.image_input.letterbox = false;
  out.image_input.mean = {0.48145466, 0.4578275, 0.40821073};
  out.image_input.std = {0.26862954, 0.26130258, 0.27577711};
  std::string image_model, text_model, merges, embeddings;
  ARTEMIS_TRY(text(j, "image_model", "clip", image_model));
  ARTEMIS_TRY(text(j, "text_model", "clip", text_model));
  ARTEMIS_TRY(text(j, "merges", "clip", merges));
  ARTEMIS_TRY(text(j, "text_embeddings", "clip", embeddings));
  if (image_model.empty()) return fail("clip.image_model (the CLIP image encoder) is missing");
  if (text_model.empty() && embeddings.empty()) {
    return fail("clip needs text_model (with merges) or text_embeddings for the prompts' embeddings");
  }
  if (!text_model.empty() && merges.empty()) return fail("clip.text_model needs clip.merges (the BPE merges file)");
  out.image_model = folder / image_model;
  if (!text_model.empty()) out.text_model = folder / text_model;
  if (!merges.empty()) out.merges = folder / merges;
  if (!embeddings.empty()) out.text_embeddings = folder / embeddings;
  if (j.contains("image_input")) ARTEMIS_TRY(input(j["image_input"], "clip.image_input", out.image_input));
  std::int64_t context = static_cast<std::int64_t>(out.context_length);
  ARTEMIS_TRY(whole(j, "context_length", "clip", 2, 4096, context));
  out.context_length = static_cast<std::size_t>(context);
  std::int64_t max_merges = static_cast<std::int64_t>(out.max_merges);
  ARTEMIS_TRY(whole(j, "max_merges", "clip", 0, 10000000, max_merges));
  out.max_merges = static_cast<std::size_t>(max_merges);
  ARTEMIS_TRY(text(j, "prompt_template", "clip", out.prompt_template));
  if (out.prompt_template.find("{}") == std::string::npos) {
    return fail("clip.prompt_template must hold {} where the class name goes");
  }
  if (j.contains("background")) {
    const Json& b = j["background"];
    if (!b.is_array() || !std::all_of(b.begin(), b.end(), [](const Json& x) { return x.is_string(); })) {
      return fail("clip.background must list prompts (strings)");
    }
    for (const Json& x : b) out.background.push_back(x.get<std::string>());
  }
  if (out.background.empty()) return fail("clip.background needs at least one prompt for \"none of the classes\"");
  ARTEMIS_TRY(number(j, "temperature", "clip", 0.001, 1e4, out.temperature));
  ARTEMIS_TRY(number(j, "threshold", "clip", 0.0, 1.0, out.threshold));
  return Status::ok();
}

Status Reader::runtime(const Json& j, onnx::RuntimeOptions& out) const {
  if (!j.is_object()) return fail("\"runtime\" must be an object");
  ARTEMIS_TRY(text(j, "library", "runtime", out.library));
  ARTEMIS_TRY(text(j, "provider", "runtime", out.provider));
  if (out.provider != "auto" && out.provider != "cpu" && out.provider != "cuda") {
    return fail(fmt::format("runtime.provider is '{}', not auto, cpu or cuda", out.provider));
  }
  std::int64_t threads = out.threads;
  ARTEMIS_TRY(whole(j, "threads", "runtime", 0, 1024, threads));
  out.threads = static_cast<int>(threads);
  return Status::ok();
}

#undef ARTEMIS_TRY

}  // namespace

Result<OnnxModelConfig> OnnxModelConfig::parse(std::string_view json, const std::string& origin,
                                               const Vocabulary& vocabulary, const std::filesystem::path& folder) {
  OnnxModelConfig c;
  c.origin = origin;
  const Reader read(origin);
  try {
    const Json j = Json::parse(json);
    if (!j.is_object()) return read.fail("a model config is a JSON object");
    if (Status st = read.text(j, "name", "config", c.name); !st.isOk()) return st;
    if (j.contains("runtime")) {
      if (Status st = read.runtime(j["runtime"], c.runtime); !st.isOk()) return st;
    }
    if (!j.contains("instances")) return read.fail("\"instances\" (the instance segmentation model) is missing");
    if (Status st = read.instances(j["instances"], vocabulary, folder, c.instances); !st.isOk()) return st;
    if (j.contains("clip")) {
      ClipConfig clip;
      if (Status st = read.clip(j["clip"], folder, clip); !st.isOk()) return st;
      c.clip = std::move(clip);
    } else if (std::all_of(c.instances.label_classes.begin(), c.instances.label_classes.end(),
                           [](ClassId id) { return id == kNoClass; })) {
      return read.fail("instances.classes maps no label to a class of the vocabulary (and there is no clip stage)");
    }
  } catch (const nlohmann::json::exception& e) {
    return parseError(fmt::format("{}: not a valid model config: {}", origin, e.what()));
  }
  return c;
}

Result<OnnxModelConfig> OnnxModelConfig::load(const std::filesystem::path& path, const Vocabulary& vocabulary) {
  auto text = io::readTextFile(path, io::limits::kJson);
  if (!text) return Status(text.status().code(), text.status().message() + " (the model config)");
  return parse(*text, path.string(), vocabulary, path.parent_path());
}

}  // namespace artemis::semantics
