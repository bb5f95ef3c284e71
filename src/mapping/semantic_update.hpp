#pragma once
// Stage 2's class update (eq. 12-13) for the vertices a view sees reliably: from a segmenter's
// masks, or from a dense segmenter's per-pixel probabilities. Internal to refinement.

#include <cstdint>
#include <vector>

#include "artemis/mapping/frame_ground.hpp"
#include "artemis/mapping/geometric_prior.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::mapping {

// A vertex the view sees, at pixel (u, v), with reliability W > 0. Every vote is a distinct vertex.
struct SemanticVote {
  std::uint32_t vertex = 0;
  int u = 0;
  int v = 0;
  float reliability = 0.0f;
};

struct MaskUpdateSettings {
  float mask_floor = 0.01f;
  float background_score = 0.5f;
  int mask_border_px = 4;
};

// Inside a mask of class c_m with score s: P_mask(o | c_m) = s, (1 - s) / (slots - 1) for the other
// slots; outside every mask "none" with the background score. Pixels within mask_border_px of
// another mask observe nothing. Runs in parallel over the votes.
void updateFromMasks(const std::vector<SemanticVote>& votes, const semantics::SemanticObservation& observation,
                     const MaskUpdateSettings& settings, SemanticMesh& mesh);

// P_mask(o | c) per slot: the pixel's probabilities weighed by the vertex's height above `ground`
// and its normal (DenseEvidence), floored at mask_floor. As with masks, a pixel whose most probable
// class differs mask_border_px away (an object's edge, where a network's labels bleed) observes
// nothing. Runs in parallel over the votes.
void updateFromDense(const std::vector<SemanticVote>& votes, const semantics::DenseProbabilities& dense,
                     const GeometricPriorParams& geometry, const semantics::Vocabulary& vocabulary,
                     const FrameGround& ground, const MaskUpdateSettings& settings, SemanticMesh& mesh);

}  // namespace artemis::mapping
