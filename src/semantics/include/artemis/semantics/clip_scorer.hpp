#pragma once
// CLIP on image crops and prompt texts (onnx_model_config.hpp, pipeline 2): unit embeddings of
// both, and per crop a softmax over the prompts and the background prompts of the cosine
// similarities times the temperature.
//
// A prompt's text embedding comes from the precomputed file (by the class name, then by the whole
// prompt text) or else from the text encoder on the tokenized prompt template; either way it is
// worked out once and kept. Crops go through the image encoder in batches of 32 when its first
// input dimension is open, one by one otherwise. The encoders' embedding is their first output of shape
// [batch, D].

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "artemis/core/image.hpp"
#include "artemis/core/status.hpp"
#include "artemis/semantics/clip_tokenizer.hpp"
#include "artemis/semantics/onnx_model_config.hpp"
#include "artemis/semantics/onnx_runtime.hpp"

namespace artemis::semantics {

class ClipScorer {
 public:
  // Opens the encoders (and reads the merges and precomputed embeddings); errors name the file.
  static Result<std::unique_ptr<ClipScorer>> open(const ClipConfig& config, const onnx::RuntimeOptions& runtime);

  // The unit text embedding of a class called `name`.
  Result<std::vector<float>> textEmbedding(const std::string& name);
  // The unit image embeddings of RGB crops, one per crop.
  Result<std::vector<std::vector<float>>> imageEmbeddings(const std::vector<ImageU8>& crops);
  // Per crop, the probabilities of each of `names` and then of each background prompt.
  Result<std::vector<std::vector<double>>> classify(const std::vector<ImageU8>& crops,
                                                    const std::vector<std::string>& names);

  [[nodiscard]] const ClipConfig& config() const { return config_; }
  // The colour a crop's pixels outside its mask take: the image input's mean, as 8-bit RGB.
  [[nodiscard]] std::array<std::uint8_t, 3> fillColour() const;

 private:
  ClipScorer() = default;
  Result<std::vector<float>> encodeText(const std::string& prompt);

  ClipConfig config_;
  std::unique_ptr<onnx::Session> image_;
  std::unique_ptr<onnx::Session> text_;
  std::optional<ClipTokenizer> tokenizer_;
  std::map<std::string, std::vector<float>> precomputed_;
  std::map<std::string, std::vector<float>> cache_;  // name -> unit embedding
};

}  // namespace artemis::semantics
