// Dense segmentation model configuration JSON (data/models/*.json, README "Bring your own model"):
// DenseModelConfig::load against the SemanticKITTI vocabulary, then the label-to-prompt mapping a
// run builds from it, applied to one pixel.
#include <numeric>
#include <vector>

#include "artemis/semantics/dense_model.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  using namespace artemis::semantics;
  const auto path = fuzz::writeInput(data, size, "model.json");
  auto config = DenseModelConfig::load(path, Vocabulary::semanticKitti());
  if (!config) return artemis::fuzz::rejected(config.status());
  if (config->labels.size() != config->label_classes.size()) {
    fuzz::invariantBroken("DenseModelConfig", "labels and label_classes differ in size");
  }
  const std::vector<float> uniform(config->labels.size(),
                                   config->labels.empty() ? 0.0f : 1.0f / static_cast<float>(config->labels.size()));
  // Prompts: none, the cars, and every class.
  std::vector<ClassId> all;
  for (const auto& c : Vocabulary::semanticKitti().classes()) all.push_back(c.id);
  for (const std::vector<ClassId>& prompts : {std::vector<ClassId>{}, std::vector<ClassId>{1}, all}) {
    const LabelToPrompts mapping(*config, prompts);
    if (mapping.channels() != prompts.size() + 1) fuzz::invariantBroken("LabelToPrompts", "channel count");
    std::vector<float> out(mapping.channels(), -1.0f);
    mapping.apply(uniform.data(), out.data());
  }
  return 0;
}
