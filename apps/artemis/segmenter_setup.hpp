#pragma once
// The segmenter of `artemis run --segmenter`, built from its settings; `artemis eval semantics
// --masks-alone` rebuilds the same one from the run's semantics.json.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "artemis/core/status.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::cli {

struct SegmenterChoice {
  std::string kind;                // "sim", "maskfile", "dnn" or "onnx"
  std::string noise = "standard";  // sim
  std::uint64_t seed = 1;          // sim
  std::string sim_gt;              // sim: empty = found beside the recording
  std::string masks;               // maskfile
  std::string model;               // dnn: the network's weights
  std::string model_config;        // dnn: how to feed and read it (DenseModelConfig); onnx: OnnxModelConfig
  int threads = 0;                 // dnn: OpenCV's threads (0: every core)
};

// Builds the segmenter for a recording in `dataset_root`; a mask file's phrases go through
// `grounder` (which must outlive the segmenter). `settings_json` receives the settings that
// rebuild it (for semantics.json).
Result<std::unique_ptr<semantics::Segmenter>> makeSegmenter(const SegmenterChoice& choice,
                                                            const semantics::Vocabulary& vocabulary,
                                                            const semantics::QueryGrounder* grounder,
                                                            const std::filesystem::path& dataset_root,
                                                            std::string* settings_json);

// Whether the choice segments any class a query names, even one the vocabulary lacks (an onnx
// config with a CLIP stage); an unreadable config is an error.
Result<bool> openVocabulary(const SegmenterChoice& choice, const semantics::Vocabulary& vocabulary);

// The choice recorded in a run's semantics.json ("segmenter", "segmenter_settings").
Result<SegmenterChoice> segmenterChoiceFromJson(const std::string& semantics_json, const std::string& origin);

}  // namespace artemis::cli
