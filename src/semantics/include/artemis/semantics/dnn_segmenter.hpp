#pragma once
// A dense segmentation network run by OpenCV's dnn module on the CPU (Torch7, ONNX, Caffe and
// TensorFlow files: whatever cv::dnn::readNet loads). The model file is the user's; how to feed and
// read it is a DenseModelConfig (data/models/ has the one for the ENet of ../shared/models).
//
// segment() returns a dense observation: per pixel the network's label probabilities (a softmax of
// raw scores where the config says so), gathered into "none" and the prompted classes
// (LabelToPrompts: labels of other classes count as none, confusable groups share their mass).
// The image is padded, never stretched, to the config's size multiple (and first scaled to
// resize_width where given); the output is cropped back and, where scaled, resized to the image.
//
// OpenCV's thread count is process-wide: open() sets it to `threads` (cv::setNumThreads). One
// network runs one image at a time (segment() may be called from any one thread at a time).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "artemis/core/image.hpp"
#include "artemis/semantics/dense_model.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::semantics {

// The network's probabilities of every label at every pixel of an image.
struct LabelProbabilities {
  int width = 0;
  int height = 0;
  std::size_t labels = 0;
  std::vector<float> p;  // pixel-major: (v * width + u) * labels + l
  // The most probable label at every pixel, row-major.
  [[nodiscard]] std::vector<std::uint16_t> argmax() const;
};

class DnnSegmenter final : public Segmenter {
 public:
  // Loads `model` (a missing, unreadable or corrupt file is an error naming it) and runs it once on
  // the config's probe size: a network that fails there, or whose output has another channel count
  // than the config's labels, is an error naming the config.
  static Result<std::unique_ptr<DnnSegmenter>> open(const std::filesystem::path& model, DenseModelConfig config,
                                                    int threads);
  ~DnnSegmenter() override;

  [[nodiscard]] std::string name() const override { return "dnn"; }
  Result<SemanticObservation> segment(const SegmentRequest& request, std::span<const ClassId> prompts) override;

  // The network on an RGB image: an error names the image size when the network rejects it.
  Result<LabelProbabilities> labelProbabilities(const ImageU8& rgb);
  [[nodiscard]] const DenseModelConfig& config() const;

 private:
  struct Impl;
  explicit DnnSegmenter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace artemis::semantics
