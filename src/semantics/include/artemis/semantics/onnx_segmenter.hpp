#pragma once
// `--segmenter onnx`: instance masks from the user's ONNX models through ONNX Runtime
// (onnx_runtime.hpp), in one of the two pipelines of onnx_model_config.hpp: an instance model whose
// labels map to the map's classes, or a "segment everything" model whose masks CLIP names, which
// segments any class the prompts name (open vocabulary).
//
// Each mask is an observation of its class with its score as sigma_mask (fusion, eq. 1; refinement,
// eq. 13); a pixel in two masks belongs to the higher-scoring one. Masks of classes not prompted are
// left out, as from a text-driven segmenter. segment() may be called from one thread at a time.

#include <memory>
#include <string>
#include <vector>

#include "artemis/core/image.hpp"
#include "artemis/semantics/clip_scorer.hpp"
#include "artemis/semantics/instance_masks.hpp"
#include "artemis/semantics/onnx_model_config.hpp"
#include "artemis/semantics/onnx_runtime.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::semantics {

class OnnxSegmenter final : public Segmenter {
 public:
  // Opens the models of `config` (their files, the runtime); `vocabulary` names the prompted
  // classes for CLIP and must outlive the segmenter. Errors name the model or the config: a
  // missing runtime or file, a model with an input the config does not name, outputs of no known
  // layout (checked on a blank image).
  static Result<std::unique_ptr<OnnxSegmenter>> open(OnnxModelConfig config, const Vocabulary& vocabulary);

  [[nodiscard]] std::string name() const override { return "onnx"; }
  [[nodiscard]] bool openVocabulary() const { return config_.openVocabulary(); }
  Result<SemanticObservation> segment(const SegmentRequest& request, std::span<const ClassId> prompts) override;

  // A detected instance: its label (the instance model's), score and mask in image pixels.
  struct Instance {
    Detection detection;
    InstanceMask mask;
  };
  // The instance model on an RGB image: its detections and their masks, best first.
  Result<std::vector<Instance>> instances(const ImageU8& rgb);
  [[nodiscard]] const OnnxModelConfig& config() const { return config_; }
  [[nodiscard]] const std::string& provider() const { return instances_->provider(); }

 private:
  OnnxSegmenter(OnnxModelConfig config, const Vocabulary& vocabulary);
  // The crop of an instance CLIP sees: the square around its box at the CLIP input's size, outside
  // the mask the fill colour.
  [[nodiscard]] ImageU8 cropOf(const ImageU8& rgb, const InstanceMask& mask) const;

  OnnxModelConfig config_;
  const Vocabulary& vocabulary_;
  std::unique_ptr<onnx::Session> instances_;
  std::unique_ptr<ClipScorer> clip_;
  onnx::Tensor input_;  // scratch
};

}  // namespace artemis::semantics
