#pragma once
// A dense segmenter's observation read for one surface point: the pixel's class probabilities,
// weighed by what the map's geometry says of each class (GeometricPrior), renormalised and laid
// out over the mesh's semantic slots. Used by fusion (eq. 1) and refinement (eq. 13) alike.
// A slot whose class the observation does not carry (prompted after the image was segmented)
// takes the "none" channel's value: the segmenter said nothing about it.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "artemis/mapping/geometric_prior.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::mapping {

class DenseEvidence {
 public:
  DenseEvidence(const semantics::DenseProbabilities& dense, const SemanticMesh& mesh,
                const GeometricPriorParams& params, const semantics::Vocabulary& vocabulary);

  // The distribution over the mesh's slots at pixel (u, v), inside the image, for a surface h_m
  // above the ground (NaN: unknown) with `normal` (nullptr: unknown), into `out` (slotCount()
  // values summing to 1). Returns its largest value: the pixel's confidence, eq. 1's sigma_mask.
  // `scratch` holds 2 * channels floats.
  float read(int u, int v, float h_m, const Eigen::Vector3f* normal, float* out, float* scratch) const;
  [[nodiscard]] std::size_t channels() const { return channel_slot_.size(); }
  [[nodiscard]] std::size_t slots() const { return slot_channel_.size(); }

 private:
  const semantics::DenseProbabilities& dense_;
  GeometricPrior prior_;
  std::vector<std::size_t> channel_slot_;
  std::vector<std::size_t> slot_channel_;  // channel 0 where the observation has no channel
};

}  // namespace artemis::mapping
