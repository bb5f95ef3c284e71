#pragma once
// Instance segmentation outputs (YOLO-seg, YOLOE, FastSAM) into masks in image pixels.
//
// Two layouts are in use, and outputs are told apart by shape, never by order or name:
//   prototypes   [1, nm, ph, pw]              nm mask prototypes at a fraction of the input size
//   dense        [1, 4 + nc + nm, N]          per candidate: centre x, y, width, height (input
//                                              pixels), nc class scores, nm mask coefficients
//                (or [1, N, 4 + nc + nm], as some exports transpose it)
//   end-to-end   [1, K, 6 + nm]               per detection: x0, y0, x1, y1, score, class, nm
//                                              coefficients (already suppressed)
// nc is the config's label count, nm the prototypes' channel count. Where the shapes allow two
// readings they are tried in the order above, dense first, end-to-end before transposed dense: an
// end-to-end [1, K, 6 + nm] whose K happens to be 4 + nc + nm reads as dense, and with nc = 2 a
// transposed dense output reads as end-to-end; a config's "layout" settles it. Candidates whose
// numbers are not finite, whose box is empty or lies beyond a million pixels, or whose class
// index is none of the labels are dropped: a model's output is not trusted.
//
// A candidate's class is its best score's; candidates below the score threshold go, the rest of
// the dense layout are suppressed per class (greedy, by IoU of their boxes). A detection's mask is
// sigmoid(coefficients . prototypes), bilinear on the prototype grid at each image pixel's place
// in the input, above the mask threshold and inside the detection's box: the image's pixels, the
// letterbox undone.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/semantics/network_input.hpp"
#include "artemis/semantics/onnx_runtime.hpp"

namespace artemis::semantics {

enum class DetectionLayout { kAuto, kDense, kDenseTransposed, kEndToEnd };
// "auto", "dense", "dense_transposed", "end_to_end"; false for another name.
bool parseLayout(const std::string& name, DetectionLayout& out);

struct Detection {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // box in input pixels
  float score = 0;
  int label = 0;
  std::vector<float> coefficients;
};

struct InstanceOutputs {
  const onnx::Tensor* detections = nullptr;
  const onnx::Tensor* prototypes = nullptr;
  DetectionLayout layout = DetectionLayout::kDense;
  int labels = 0;        // nc
  int coefficients = 0;  // nm
};

// Finds the detections and prototypes among a model's outputs for `labels` classes, in `layout`
// (kAuto: by shape); an error names the model and lists what it returned.
Result<InstanceOutputs> identifyInstanceOutputs(std::span<const onnx::Tensor> outputs, int labels,
                                                const std::string& model,
                                                DetectionLayout layout = DetectionLayout::kAuto);

struct DetectionParams {
  float score_threshold = 0.25f;
  float iou_threshold = 0.45f;
  std::size_t max_detections = 100;
};

// The detections above the score threshold, suppressed (dense layouts), best first.
std::vector<Detection> readDetections(const InstanceOutputs& outputs, const DetectionParams& params);

// Greedy non-maximum suppression per label: a detection goes when a better one of its label
// overlaps it by more than `iou`. Keeps at most `max` (best first).
std::vector<Detection> suppress(std::vector<Detection> detections, float iou, std::size_t max);

// A detection's mask over the image: the pixels of its box (image pixels, clipped to the image)
// whose mask probability exceeds `threshold`.
struct InstanceMask {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // the box's pixels [x0, x1) x [y0, y1)
  std::vector<std::uint8_t> inside;    // (y - y0) * (x1 - x0) + (x - x0)
  std::size_t pixels = 0;              // how many are inside
  [[nodiscard]] bool contains(int x, int y) const {
    return x >= x0 && y >= y0 && x < x1 && y < y1 &&
           inside[static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(x1 - x0) +
                  static_cast<std::size_t>(x - x0)] != 0;
  }
};
InstanceMask maskOf(const Detection& detection, const onnx::Tensor& prototypes, const Placement& placement,
                    int input_width, int input_height, float threshold);

}  // namespace artemis::semantics
