#include "semantic_update.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "artemis/mapping/dense_evidence.hpp"

namespace artemis::mapping {

void updateFromMasks(const std::vector<SemanticVote>& votes, const semantics::SemanticObservation& observation,
                     const MaskUpdateSettings& settings, SemanticMesh& mesh) {
  // log P_mask per mask id (0: outside every mask): of its own slot, and of every other slot.
  const float slots = static_cast<float>(mesh.slotCount());
  const float floor = settings.mask_floor;
  const auto likelihood = [&](double score) {
    const auto s = static_cast<float>(score);
    return std::pair{std::log(std::max(s, floor)), std::log(std::max((1.0f - s) / (slots - 1.0f), floor))};
  };
  struct MaskTerm {
    std::size_t slot;
    float log_hit;
    float log_miss;
  };
  std::vector<MaskTerm> terms;
  terms.reserve(observation.masks.size() + 1);
  const auto [bg_hit, bg_miss] = likelihood(settings.background_score);
  terms.push_back({0, bg_hit, bg_miss});
  for (const semantics::Mask& m : observation.masks) {
    const int slot = mesh.slotOf(m.class_id);
    if (slot < 0) throw std::logic_error("refinement: a mask's class has no slot in the mesh");
    const auto [hit, miss] = likelihood(m.score);
    terms.push_back({static_cast<std::size_t>(slot), hit, miss});
  }
  mesh.reserveRefinement();
  const ImageU16& ids = observation.mask_ids;
  const int border = settings.mask_border_px;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, votes.size(), 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const SemanticVote& c = votes[k];
      if (!ids.contains(c.u, c.v)) continue;
      const std::size_t id = ids.at(c.u, c.v);
      if (id >= terms.size()) continue;  // not a mask of this observation (validate() reports these)
      if (border > 0) {
        bool inside = true;
        for (int dv = -border; dv <= border && inside; dv += border) {
          for (int du = -border; du <= border && inside; du += border) {
            const int x = std::clamp(c.u + du, 0, ids.width() - 1);
            const int y = std::clamp(c.v + dv, 0, ids.height() - 1);
            inside = ids.at(x, y) == id;
          }
        }
        if (!inside) continue;
      }
      const MaskTerm& term = terms[id];
      mesh.addLogLikelihood(c.vertex, term.slot, term.log_hit, term.log_miss, c.reliability);
    }
  });
}

void updateFromDense(const std::vector<SemanticVote>& votes, const semantics::DenseProbabilities& dense,
                     const GeometricPriorParams& geometry, const semantics::Vocabulary& vocabulary,
                     const FrameGround& ground, const MaskUpdateSettings& settings, SemanticMesh& mesh) {
  const DenseEvidence evidence(dense, mesh, geometry, vocabulary);
  const int border = settings.mask_border_px;
  const float mask_floor = settings.mask_floor;
  const auto interior = [&](int u, int v) {
    const semantics::ClassId centre = dense.argmax(u, v);
    for (int dv = -border; dv <= border; dv += border) {
      for (int du = -border; du <= border; du += border) {
        const int x = std::clamp(u + du, 0, dense.width - 1);
        const int y = std::clamp(v + dv, 0, dense.height - 1);
        if (dense.argmax(x, y) != centre) return false;
      }
    }
    return true;
  };
  mesh.reserveRefinement();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, votes.size(), 4096), [&](const auto& range) {
    std::vector<float> p(evidence.slots());
    std::vector<float> scratch(2 * evidence.channels());
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const SemanticVote& c = votes[k];
      if (!dense.contains(c.u, c.v)) continue;
      if (border > 0 && !interior(c.u, c.v)) continue;
      const Eigen::Vector3f& p_W = mesh.positions()[c.vertex];
      const Eigen::Vector3f& normal = mesh.normals()[c.vertex];
      evidence.read(c.u, c.v, ground.heightAbove(p_W), &normal, p.data(), scratch.data());
      for (float& q : p) q = std::log(std::max(q, mask_floor));
      mesh.addLogLikelihoods(c.vertex, p.data(), c.reliability);
    }
  });
}

}  // namespace artemis::mapping
