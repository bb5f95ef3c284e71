#pragma once
// How `--segmenter onnx` runs the user's ONNX models: a data file (README, "Open vocabulary"). Model
// and merges paths are relative to the config's folder. Two pipelines:
//
// 1. Instance segmentation with the vocabulary baked in (YOLO-seg, YOLOE exported with its class
//    prompts): the network's labels map to the map's classes.
//   {
//     "name": "yoloe-11s-seg",
//     "runtime": {"library": "", "provider": "auto", "threads": 0},      all optional
//     "instances": {
//       "model": "yoloe-11s-seg.onnx",
//       "input": {"name": "images", "size": [640, 640], "letterbox": true, "pad_value": 114,
//                 "scale": 0.00392156862745098, "mean": [0, 0, 0], "std": [1, 1, 1],
//                 "channel_order": "rgb", "interpolation": "linear"},   every key optional
//       "score_threshold": 0.25, "iou_threshold": 0.45, "mask_threshold": 0.5, "max_detections": 100,
//       "layout": "auto",          or dense, dense_transposed, end_to_end (instance_masks.hpp)
//       "labels": ["person", "bicycle", "car", ...],   the network's classes, in its order
//       "classes": {"person": "person", "bus": "other-vehicle", "bench": null}
//     }                                                label -> vocabulary class; null or absent: none
//   }
//
// 2. "Segment everything" (FastSAM) and CLIP: every mask the instances model finds (its labels are
//    then only counted, e.g. ["object"]) is cropped from the image, the rest of its box filled with
//    the CLIP input's mean colour, embedded by the CLIP image encoder and compared with the text
//    embeddings of the prompted classes and of background prompts (cosine similarity times
//    `temperature`, a softmax over all of them). A mask takes the best prompted class when it wins
//    with at least `threshold` of the probability, its score that probability. Any class name can
//    be prompted, so a query the vocabulary lacks becomes an open class (Vocabulary::addOpenClass).
//   {
//     "instances": {"model": "FastSAM-s.onnx", "labels": ["object"], "score_threshold": 0.4, ...},
//     "clip": {
//       "image_model": "clip-vit-b32-image.onnx",
//       "image_input": {"size": [224, 224], "mean": [0.48145466, 0.4578275, 0.40821073],
//                       "std": [0.26862954, 0.26130258, 0.27577711]},        defaults: CLIP's
//       "text_model": "clip-vit-b32-text.onnx", "merges": "bpe_simple_vocab_16e6.txt.gz",
//       "text_embeddings": "embeddings.json",   instead of, or before, the text model:
//                                               {"car": [...], "road": [...]} by class or prompt name
//       "context_length": 77, "prompt_template": "a photo of a {}",
//       "background": ["road", "sky", "building", "tree", "thing"],
//       "temperature": 100, "threshold": 0.5
//     }
//   }

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/semantics/instance_masks.hpp"
#include "artemis/semantics/network_input.hpp"
#include "artemis/semantics/onnx_runtime.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::semantics {

struct InstanceModelConfig {
  std::filesystem::path model;
  NetworkInput input;
  DetectionParams detection;
  DetectionLayout layout = DetectionLayout::kAuto;
  float mask_threshold = 0.5f;
  std::vector<std::string> labels;
  std::vector<ClassId> label_classes;  // label -> vocabulary class (kNoClass: none)
};

struct ClipConfig {
  std::filesystem::path image_model;
  NetworkInput image_input;
  std::filesystem::path text_model;       // empty: text_embeddings only
  std::filesystem::path merges;           // with text_model
  std::filesystem::path text_embeddings;  // empty: text_model only
  std::size_t context_length = 77;
  std::size_t max_merges = 49152 - 256 - 2;
  std::string prompt_template = "a photo of a {}";
  std::vector<std::string> background;
  double temperature = 100.0;
  double threshold = 0.5;
};

struct OnnxModelConfig {
  std::string name;
  std::string origin;  // the file it came from
  onnx::RuntimeOptions runtime;
  InstanceModelConfig instances;
  std::optional<ClipConfig> clip;

  [[nodiscard]] bool openVocabulary() const { return clip.has_value(); }

  // Parses the JSON text against `vocabulary`; relative paths are taken from `folder`.
  static Result<OnnxModelConfig> parse(std::string_view json, const std::string& origin, const Vocabulary& vocabulary,
                                       const std::filesystem::path& folder);
  static Result<OnnxModelConfig> load(const std::filesystem::path& path, const Vocabulary& vocabulary);
};

}  // namespace artemis::semantics
