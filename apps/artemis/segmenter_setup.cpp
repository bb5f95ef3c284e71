#include "segmenter_setup.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <thread>

#include "artemis/semantics/dnn_segmenter.hpp"
#include "artemis/semantics/mask_file_segmenter.hpp"
#include "artemis/semantics/onnx_segmenter.hpp"
#include "artemis/semantics/simulated_segmenter.hpp"

namespace artemis::cli {

namespace fs = std::filesystem;

namespace {

// The simulator's gt/ folder for a recording it wrote: <root>/gt beside sequences/, found by
// walking up from the dataset's folder (sequences/00 -> the simulation's root).
Result<fs::path> findSimGroundTruth(const fs::path& dataset_root) {
  for (fs::path p = fs::absolute(dataset_root); !p.empty(); p = p.parent_path()) {
    if (fs::is_directory(p / "gt" / "semantic_2")) return p / "gt";
    if (p == p.parent_path()) break;
  }
  return notFound(
      fmt::format("{}: no simulator ground truth (gt/semantic_2) found beside this recording; --segmenter sim works on "
                  "`artemis sim` output (or give --sim-gt)",
                  dataset_root.string()));
}

}  // namespace

Result<std::unique_ptr<semantics::Segmenter>> makeSegmenter(const SegmenterChoice& choice,
                                                            const semantics::Vocabulary& vocabulary,
                                                            const semantics::QueryGrounder* grounder,
                                                            const fs::path& dataset_root, std::string* settings_json) {
  nlohmann::ordered_json settings;
  std::unique_ptr<semantics::Segmenter> segmenter;
  if (choice.kind == "sim") {
    auto noise = semantics::noiseProfile(choice.noise);
    if (!noise) return noise.status();
    fs::path gt = choice.sim_gt;
    if (gt.empty()) {
      auto found = findSimGroundTruth(dataset_root);
      if (!found) return found.status();
      gt = *found;
    }
    auto seg = semantics::SimulatedSegmenter::open(gt, vocabulary, *noise, choice.seed);
    if (!seg) return seg.status();
    segmenter = std::move(*seg);
    settings = {{"ground_truth", fs::absolute(gt).string()}, {"noise", choice.noise}, {"seed", choice.seed}};
  } else if (choice.kind == "maskfile") {
    if (choice.masks.empty())
      return invalidArgument("--segmenter maskfile needs --masks DIR (the folder of mask files)");
    semantics::PhraseResolver resolver;
    if (grounder != nullptr) {
      // A mask's phrase goes through the same grounding as the queries.
      resolver = [grounder](const std::string& text) -> Result<semantics::ClassId> {
        auto grounding = grounder->ground(text);
        if (!grounding) return grounding.status();
        if (grounding->classes.size() != 1) {
          return invalidArgument(grounding->classes.empty() ? fmt::format("no class matches '{}'", text)
                                                            : fmt::format("phrase '{}' matches {} classes, not one",
                                                                          text, grounding->classes.size()));
        }
        return grounding->classes.front();
      };
    }
    auto seg = semantics::MaskFileSegmenter::open(choice.masks, vocabulary, resolver);
    if (!seg) return seg.status();
    segmenter = std::move(*seg);
    settings = {{"masks", fs::absolute(choice.masks).string()}};
  } else if (choice.kind == "dnn") {
    if (choice.model.empty() || choice.model_config.empty()) {
      return invalidArgument(
          "--segmenter dnn needs --model WEIGHTS and --model-config CONFIG.json (for the ENet of the README: "
          "data/models/enet-cityscapes.json)");
    }
    auto config = semantics::DenseModelConfig::load(choice.model_config, vocabulary);
    if (!config) return config.status();
    const int threads =
        choice.threads > 0 ? choice.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    auto seg = semantics::DnnSegmenter::open(choice.model, std::move(*config), threads);
    if (!seg) return seg.status();
    segmenter = std::move(*seg);
    settings = {{"model", fs::absolute(choice.model).string()},
                {"model_config", fs::absolute(choice.model_config).string()},
                {"threads", choice.threads}};
  } else if (choice.kind == "onnx") {
    if (choice.model_config.empty()) {
      return invalidArgument(
          "--segmenter onnx needs --model-config CONFIG.json (the models and how to run them; see "
          "the README's \"Open vocabulary\")");
    }
    auto config = semantics::OnnxModelConfig::load(choice.model_config, vocabulary);
    if (!config) return config.status();
    if (config->runtime.threads == 0 && choice.threads > 0) config->runtime.threads = choice.threads;
    auto seg = semantics::OnnxSegmenter::open(std::move(*config), vocabulary);
    if (!seg) return seg.status();
    settings = {{"model_config", fs::absolute(choice.model_config).string()},
                {"provider", (*seg)->provider()},
                {"threads", choice.threads}};
    segmenter = std::move(*seg);
  } else {
    return invalidArgument(fmt::format("unknown segmenter '{}' (sim, maskfile, dnn or onnx)", choice.kind));
  }
  if (settings_json != nullptr) *settings_json = settings.dump();
  return segmenter;
}

Result<bool> openVocabulary(const SegmenterChoice& choice, const semantics::Vocabulary& vocabulary) {
  if (choice.kind != "onnx" || choice.model_config.empty()) return false;
  auto config = semantics::OnnxModelConfig::load(choice.model_config, vocabulary);
  if (!config) return config.status();
  return config->openVocabulary();
}

Result<SegmenterChoice> segmenterChoiceFromJson(const std::string& semantics_json, const std::string& origin) {
  try {
    const auto j = nlohmann::json::parse(semantics_json);
    SegmenterChoice c;
    c.kind = j.at("segmenter").get<std::string>();
    const auto& s = j.at("segmenter_settings");
    if (c.kind == "sim") {
      c.sim_gt = s.at("ground_truth").get<std::string>();
      c.noise = s.at("noise").get<std::string>();
      c.seed = s.at("seed").get<std::uint64_t>();
    } else if (c.kind == "dnn") {
      c.model = s.at("model").get<std::string>();
      c.model_config = s.at("model_config").get<std::string>();
      c.threads = s.value("threads", 0);
    } else if (c.kind == "onnx") {
      c.model_config = s.at("model_config").get<std::string>();
      c.threads = s.value("threads", 0);
    } else {
      c.masks = s.at("masks").get<std::string>();
    }
    return c;
  } catch (const nlohmann::json::exception& e) {
    return parseError(fmt::format("{}: no usable segmenter settings: {}", origin, e.what()));
  }
}

}  // namespace artemis::cli
