#include "artemis/semantics/dense_model.hpp"
#include "artemis/io/read_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

namespace artemis::semantics {

namespace {

using Json = nlohmann::json;

// A model config is a few kB; anything much larger is not one (and /dev/zero never ends).
constexpr std::size_t kMaxConfigBytes = 1 << 20;

// A whole number within [min, max]: get<int>() of 1e10 is undefined behaviour, and of 8.9 is 8.
Status wholeNumber(const Json& v, int min, int max, const std::string& what, int& out) {
  if (!v.is_number_integer() || v.get<std::int64_t>() < min || v.get<std::int64_t>() > max) {
    return parseError(fmt::format("{} must be a whole number in {}..{}, not {}", what, min, max, v.dump()));
  }
  out = static_cast<int>(v.get<std::int64_t>());
  return Status::ok();
}

Status parseInput(const Json& j, const std::string& origin, DenseModelInput& in) {
  if (!j.is_object()) return parseError(origin + ": \"input\" is not an object");
  if (j.contains("size_multiple")) {
    if (Status s = wholeNumber(j["size_multiple"], 1, 256, origin + ": input.size_multiple", in.size_multiple);
        !s.isOk()) {
      return s;
    }
  }
  if (j.contains("resize_width")) {
    if (Status s = wholeNumber(j["resize_width"], 0, 16384, origin + ": input.resize_width", in.resize_width);
        !s.isOk()) {
      return s;
    }
  }
  in.scale = j.value("scale", in.scale);
  if (j.contains("mean")) {
    const Json& m = j["mean"];
    if (!m.is_array() || m.size() != 3) return parseError(origin + ": input.mean must hold 3 numbers");
    for (std::size_t c = 0; c < 3; ++c) in.mean[c] = m[c].get<double>();
  }
  const std::string order = j.value("channel_order", std::string("rgb"));
  if (order != "rgb" && order != "bgr") {
    return parseError(fmt::format("{}: input.channel_order is '{}', expected rgb or bgr", origin, order));
  }
  in.bgr = order == "bgr";
  if (j.contains("probe_size")) {
    const Json& p = j["probe_size"];
    if (!p.is_array() || p.size() != 2) return parseError(origin + ": input.probe_size must be [width, height]");
    for (std::size_t k = 0; k < 2; ++k) {
      if (Status s = wholeNumber(p[k], 1, 4096, origin + ": input.probe_size", in.probe_size[k]); !s.isOk()) return s;
    }
  }
  if (in.size_multiple < 1 || in.size_multiple > 256 || in.resize_width < 0 || in.resize_width > 16384 ||
      !(std::isfinite(in.scale) && in.scale != 0.0) || in.probe_size[0] < 1 || in.probe_size[1] < 1 ||
      in.probe_size[0] > 4096 || in.probe_size[1] > 4096) {
    return parseError(origin +
                      ": input: size_multiple must be in 1..256, resize_width in 0..16384, scale finite and not 0, "
                      "probe_size in 1..4096");
  }
  return Status::ok();
}

Result<ClassId> classNamed(const Vocabulary& vocabulary, const std::string& name, const std::string& origin,
                           std::string_view where) {
  const SemanticClass* cls = vocabulary.findByName(name);
  if (cls == nullptr) {
    return parseError(fmt::format("{}: {} names '{}', which is not a class of the vocabulary", origin, where, name));
  }
  return cls->id;
}

Status parseClasses(const Json& j, const std::string& origin, const Vocabulary& vocabulary, DenseModelConfig& c) {
  const Json& labels = j.at("labels");
  if (!labels.is_array() || labels.empty()) return parseError(origin + ": \"labels\" must be a non-empty array");
  const Json& classes = j.at("classes");
  if (!classes.is_object()) return parseError(origin + ": \"classes\" must be an object (label -> class or null)");
  for (const Json& l : labels) {
    const auto label = l.get<std::string>();
    if (std::find(c.labels.begin(), c.labels.end(), label) != c.labels.end()) {
      return parseError(fmt::format("{}: label '{}' is listed twice", origin, label));
    }
    if (!classes.contains(label)) {
      return parseError(
          fmt::format("{}: label '{}' has no entry in \"classes\" (give a class, or null)", origin, label));
    }
    ClassId id = kNoClass;
    if (const Json& target = classes[label]; !target.is_null()) {
      auto found = classNamed(vocabulary, target.get<std::string>(), origin, fmt::format("label '{}'", label));
      if (!found) return found.status();
      id = *found;
    }
    c.labels.push_back(label);
    c.label_classes.push_back(id);
  }
  for (const auto& [label, target] : classes.items()) {
    if (std::find(c.labels.begin(), c.labels.end(), label) == c.labels.end()) {
      return parseError(fmt::format("{}: \"classes\" maps '{}', which is not in \"labels\"", origin, label));
    }
  }
  std::set<ClassId> grouped;
  for (const Json& g : j.value("confusable", Json::array())) {
    std::vector<ClassId> group;
    for (const Json& name : g) {
      auto found = classNamed(vocabulary, name.get<std::string>(), origin, "a confusable group");
      if (!found) return found.status();
      if (!grouped.insert(*found).second) {
        return parseError(fmt::format("{}: class '{}' is in more than one confusable group (or twice)", origin,
                                      name.get<std::string>()));
      }
      group.push_back(*found);
    }
    if (group.size() >= 2) c.confusable.push_back(std::move(group));
  }
  return Status::ok();
}

}  // namespace

Result<DenseModelConfig> DenseModelConfig::parse(std::string_view json, const std::string& origin,
                                                 const Vocabulary& vocabulary) {
  DenseModelConfig c;
  c.origin = origin;
  try {
    const Json j = Json::parse(json);
    if (!j.is_object()) return parseError(origin + ": a model config is a JSON object");
    c.name = j.value("name", std::string("dense model"));
    if (j.contains("input")) {
      if (Status s = parseInput(j["input"], origin, c.input); !s.isOk()) return s;
    }
    const std::string output = j.value("output", std::string("scores"));
    if (output != "scores" && output != "probabilities") {
      return parseError(fmt::format("{}: \"output\" is '{}', expected scores or probabilities", origin, output));
    }
    c.output_scores = output == "scores";
    if (!j.contains("labels") || !j.contains("classes")) {
      return parseError(origin + ": a model config needs \"labels\" and \"classes\"");
    }
    if (Status s = parseClasses(j, origin, vocabulary, c); !s.isOk()) return s;
  } catch (const nlohmann::json::exception& e) {
    return parseError(fmt::format("{}: not a usable model config: {}", origin, e.what()));
  }
  return c;
}

Result<DenseModelConfig> DenseModelConfig::load(const std::filesystem::path& path, const Vocabulary& vocabulary) {
  auto text = io::readTextFile(path, io::FileLimit{kMaxConfigBytes, "a model config"});
  if (!text) return text.status();
  return parse(*text, path.string(), vocabulary);
}

LabelToPrompts::LabelToPrompts(const DenseModelConfig& config, const std::vector<ClassId>& prompts)
    : channels_(prompts.size() + 1), direct_(config.labels.size(), 0), shared_(config.labels.size(), false) {
  const auto channelOf = [&prompts](ClassId c) -> std::size_t {
    const auto it = std::find(prompts.begin(), prompts.end(), c);
    return it == prompts.end() ? 0 : static_cast<std::size_t>(it - prompts.begin()) + 1;
  };
  for (std::size_t l = 0; l < config.labels.size(); ++l) {
    direct_[l] = config.label_classes[l] == kNoClass ? 0 : channelOf(config.label_classes[l]);
  }
  for (const std::vector<ClassId>& members : config.confusable) {
    Group g;
    for (const ClassId c : members) {
      if (const std::size_t ch = channelOf(c); ch > 0) g.channels.push_back(ch);
    }
    if (g.channels.empty()) continue;  // no member prompted: the group's mass is "none"
    for (std::size_t l = 0; l < config.labels.size(); ++l) {
      const ClassId c = config.label_classes[l];
      if (c != kNoClass && direct_[l] == 0 && std::find(members.begin(), members.end(), c) != members.end()) {
        g.labels.push_back(l);
        shared_[l] = true;
      }
    }
    if (!g.labels.empty()) groups_.push_back(std::move(g));
  }
}

void LabelToPrompts::apply(const float* label_p, float* out) const {
  std::fill(out, out + channels_, 0.0f);
  for (std::size_t l = 0; l < direct_.size(); ++l) {
    if (!shared_[l]) out[direct_[l]] += label_p[l];
  }
  for (const Group& g : groups_) {
    float unprompted = 0.0f;
    for (const std::size_t l : g.labels) unprompted += label_p[l];
    float prompted = 0.0f;
    for (const std::size_t ch : g.channels) prompted += out[ch];
    if (prompted > 1e-6f) {
      const float k = unprompted / prompted;
      for (const std::size_t ch : g.channels) out[ch] += out[ch] * k;
    } else {
      const float share = unprompted / static_cast<float>(g.channels.size());
      for (const std::size_t ch : g.channels) out[ch] += share;
    }
  }
}

}  // namespace artemis::semantics
