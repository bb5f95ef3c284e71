#pragma once
// 2-D segmentation of a camera image into the prompted classes (paper §III-B: text prompts in,
// masks out). A segmenter returns masks, each with a class and a score in [0, 1], as an image of
// mask ids (one mask per pixel: where masks overlap, the one with the higher score) plus the mask
// list. A pixel inside mask m says "class m.class_id" with confidence m.score; a pixel outside
// every mask says "none of the prompted classes" (the background observation of eq. 12-13).
// Only prompted classes are returned, as from a text-driven segmenter.
//
// A dense network (one class distribution per pixel) fills `dense` instead: per pixel a
// probability for "none of the prompted classes" and for each prompted class. Fusion (eq. 1) and
// refinement (eq. 13) then read the pixel's whole distribution rather than one mask's class.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/core/image.hpp"
#include "artemis/core/status.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::semantics {

struct Mask {
  ClassId class_id = kNoClass;
  float score = 0.0f;  // the segmenter's confidence, [0, 1]
};

// Per-pixel class probabilities over `classes` (channel 0 is kNoClass, "none of the prompted
// classes"; then prompted classes), quantised to steps of 1/255: 1242 x 375 pixels and four
// channels keep in 1.9 MB while the view waits for stage 2.
struct DenseProbabilities {
  int width = 0;
  int height = 0;
  std::vector<ClassId> classes;      // channel -> class; classes[0] == kNoClass
  std::vector<std::uint8_t> values;  // pixel-major: (v * width + u) * channels() + c, probability * 255
  // The most probable channel of each pixel, row-major, where the segmenter filled it (empty:
  // argmax() works it out from `values`): refinement asks it of 9 pixels per vertex.
  std::vector<std::uint8_t> top;

  [[nodiscard]] bool empty() const { return values.empty(); }
  [[nodiscard]] std::size_t channels() const { return classes.size(); }
  [[nodiscard]] bool contains(int u, int v) const { return u >= 0 && v >= 0 && u < width && v < height; }
  // The channels of pixel (u, v); no bounds check (use contains()).
  [[nodiscard]] const std::uint8_t* at(int u, int v) const {
    return &values[(static_cast<std::size_t>(v) * static_cast<std::size_t>(width) + static_cast<std::size_t>(u)) *
                   classes.size()];
  }
  // The most probable channel's class at (u, v) (ties go to the lower channel); kNoClass outside.
  [[nodiscard]] ClassId argmax(int u, int v) const;
};

struct SemanticObservation {
  // False when the frame has no semantic observation (e.g. no mask file for it): fusion skips the
  // frame rather than reading it as "background everywhere".
  bool observed = false;
  std::string note;   // why not observed
  ImageU16 mask_ids;  // 0: no mask; k >= 1: masks[k - 1]
  std::vector<Mask> masks;

  DenseProbabilities dense;  // a dense segmenter's output; then mask_ids and masks stay empty

  [[nodiscard]] bool isDense() const { return !dense.empty(); }
  [[nodiscard]] int width() const { return isDense() ? dense.width : mask_ids.width(); }
  [[nodiscard]] int height() const { return isDense() ? dense.height : mask_ids.height(); }
  // The class the observation gives pixel (u, v): its mask's, or the dense distribution's most
  // probable; kNoClass outside every mask and outside the image.
  [[nodiscard]] ClassId classAt(int u, int v) const {
    if (isDense()) return dense.argmax(u, v);
    const Mask* m = maskAt(u, v);
    return m == nullptr ? kNoClass : m->class_id;
  }
  // The mask at pixel (u, v), or nullptr for background and pixels outside the image.
  [[nodiscard]] const Mask* maskAt(int u, int v) const {
    if (!mask_ids.contains(u, v)) return nullptr;
    const std::uint16_t id = mask_ids.at(u, v);
    return id == 0 ? nullptr : &masks[id - 1];
  }
  // Checks the invariants: ids within the list, classes among `prompts`, scores in [0, 1]; a dense
  // part's size, channel 0 kNoClass and its other classes among `prompts`.
  [[nodiscard]] Status validate(std::span<const ClassId> prompts) const;
};

// What a segmenter is asked to segment: the frame's recording index and one of its camera views.
struct SegmentRequest {
  std::size_t frame_index = 0;
  const CameraView* view = nullptr;
};

class Segmenter {
 public:
  virtual ~Segmenter() = default;
  Segmenter() = default;
  Segmenter(const Segmenter&) = delete;
  Segmenter& operator=(const Segmenter&) = delete;

  // "sim", "maskfile", ...
  [[nodiscard]] virtual std::string name() const = 0;
  // Masks of the prompted classes in the request's image. An error names the file or the problem
  // (a mask image of the wrong size, an unknown class, a bad score); the caller logs it and treats
  // the frame as unobserved. An empty prompt list gives an observed frame with no mask.
  virtual Result<SemanticObservation> segment(const SegmentRequest& request, std::span<const ClassId> prompts) = 0;
};

}  // namespace artemis::semantics
