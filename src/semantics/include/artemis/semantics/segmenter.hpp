#pragma once
// 2-D segmentation of a camera image into the prompted classes (paper §III-B: text prompts in,
// masks out). A segmenter returns masks, each with a class and a score in [0, 1], as an image of
// mask ids (one mask per pixel: where masks overlap, the one with the higher score) plus the mask
// list. A pixel inside mask m says "class m.class_id" with confidence m.score; a pixel outside
// every mask says "none of the prompted classes" (the background observation of eq. 12-13).
// Only prompted classes are returned, as from a text-driven segmenter.

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

struct SemanticObservation {
  // False when the frame has no semantic observation (e.g. no mask file for it): fusion skips the
  // frame rather than reading it as "background everywhere".
  bool observed = false;
  std::string note;   // why not observed
  ImageU16 mask_ids;  // 0: no mask; k >= 1: masks[k - 1]
  std::vector<Mask> masks;

  // The mask at pixel (u, v), or nullptr for background and pixels outside the image.
  [[nodiscard]] const Mask* maskAt(int u, int v) const {
    if (!mask_ids.contains(u, v)) return nullptr;
    const std::uint16_t id = mask_ids.at(u, v);
    return id == 0 ? nullptr : &masks[id - 1];
  }
  // Checks the invariants: ids within the list, classes among `prompts`, scores in [0, 1].
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
