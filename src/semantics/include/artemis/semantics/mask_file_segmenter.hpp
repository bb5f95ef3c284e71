#pragma once
// Masks written by any external segmenter (Grounded-SAM, FastSAM, ...), one pair of files per
// frame in a folder:
//
//   <dir>/NNNNNN.png    8- or 16-bit grey image of mask ids, the camera image's size; 0 = no mask
//   <dir>/NNNNNN.json   {"masks": [{"id": 1, "class": "car", "score": 0.91},
//                                  {"id": 2, "text": "parked van", "score": 0.62}, ...]}
//
// NNNNNN is the frame's recording index (as the LiDAR scans are numbered). Each mask names a class
// of the vocabulary ("class") or gives the segmenter's phrase ("text"), which the run's query
// grounding turns into a class. Masks of classes that were not prompted are left out (their pixels
// read as background), as a text-driven segmenter would not have returned them.
//
// A frame without its PNG or JSON has no semantic observation (logged by the caller). A mask image
// of the wrong size, an id in the image that the JSON does not list, an unknown class, a phrase
// that grounds to no single class, or a score outside [0, 1] are errors naming the file.

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "artemis/semantics/segmenter.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::semantics {

// Turns a segmenter's phrase into one class, or an error saying why not.
using PhraseResolver = std::function<Result<ClassId>(const std::string& text)>;

class MaskFileSegmenter final : public Segmenter {
 public:
  // `dir` must exist. Without a resolver, masks with "text" are errors.
  static Result<std::unique_ptr<MaskFileSegmenter>> open(const std::filesystem::path& dir, const Vocabulary& vocabulary,
                                                         PhraseResolver resolver = {});

  [[nodiscard]] std::string name() const override { return "maskfile"; }
  Result<SemanticObservation> segment(const SegmentRequest& request, std::span<const ClassId> prompts) override;

 private:
  MaskFileSegmenter(std::filesystem::path dir, Vocabulary vocabulary, PhraseResolver resolver);

  std::filesystem::path dir_;
  Vocabulary vocabulary_;
  PhraseResolver resolver_;
};

}  // namespace artemis::semantics
