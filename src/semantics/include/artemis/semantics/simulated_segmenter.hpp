#pragma once
// A stand-in for a text-driven segmenter on simulated data: it reads the simulator's ground-truth
// class and instance images (<gt>/semantic_2/NNNNNN.png, <gt>/instance_2/NNNNNN.png) and corrupts
// them with a named noise profile, deterministically from a seed (each frame's noise depends only
// on the seed and the frame index, not on the order frames are asked for).
//
// Profiles (`heavy` doubles every rate and the edge jitter of `standard`):
//   none      every instance of a prompted class is a mask with score 1, exact to the pixel.
//   standard  per instance: missed with probability 0.10; otherwise its mask is eroded or dilated
//             (equally likely) by a radius drawn from 0..4 px (square structuring element);
//             3 % of mask pixels are flipped to another prompted class (none when one class is
//             prompted); one false-positive blob per frame (a disc of 0.5 % of the image, a random
//             prompted class); scores drawn from U(0.5, 0.95) for true masks, U(0.3, 0.7) for false
//             ones. Flipped pixels keep their mask's score.
// Masks overlap after dilation: each pixel shows the mask with the highest score.

#include <filesystem>
#include <memory>
#include <string>

#include "artemis/semantics/segmenter.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::semantics {

struct SegmenterNoise {
  double miss_rate = 0.0;    // share of instances missed per frame
  int max_edge_px = 0;       // erode or dilate by 0..max_edge_px
  double flip_rate = 0.0;    // share of mask pixels flipped to another prompted class
  int false_blobs = 0;       // false-positive blobs per frame
  double blob_area = 0.005;  // of the image, each
  bool exact_scores = true;  // scores 1 (none) or drawn (standard, heavy)
};

// "none", "standard" or "heavy"; an unknown name is an error listing these.
Result<SegmenterNoise> noiseProfile(const std::string& name);

class SimulatedSegmenter final : public Segmenter {
 public:
  // `gt_dir` holds semantic_2/ and instance_2/ (the simulator's gt/ folder). Class ids in the
  // images are dataset label ids, mapped to classes through `vocabulary`.
  static Result<std::unique_ptr<SimulatedSegmenter>> open(const std::filesystem::path& gt_dir,
                                                          const Vocabulary& vocabulary, const SegmenterNoise& noise,
                                                          std::uint64_t seed);

  [[nodiscard]] std::string name() const override { return "sim"; }
  Result<SemanticObservation> segment(const SegmentRequest& request, std::span<const ClassId> prompts) override;

  // The corruption itself, for tests: class and instance images (dataset label ids) in, masks out.
  SemanticObservation corrupt(const ImageU16& classes, const ImageU16& instances, std::size_t frame_index,
                              std::span<const ClassId> prompts) const;

 private:
  SimulatedSegmenter(std::filesystem::path gt_dir, Vocabulary vocabulary, SegmenterNoise noise, std::uint64_t seed);

  std::filesystem::path gt_dir_;
  Vocabulary vocabulary_;
  SegmenterNoise noise_;
  std::uint64_t seed_;
};

}  // namespace artemis::semantics
