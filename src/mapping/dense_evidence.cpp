#include "artemis/mapping/dense_evidence.hpp"

#include <algorithm>
#include <stdexcept>

namespace artemis::mapping {

DenseEvidence::DenseEvidence(const semantics::DenseProbabilities& dense, const SemanticMesh& mesh,
                             const GeometricPriorParams& params, const semantics::Vocabulary& vocabulary)
    : dense_(dense), prior_(params, dense.classes, vocabulary), slot_channel_(mesh.slotCount(), 0) {
  for (std::size_t c = 0; c < dense.classes.size(); ++c) {
    const int slot = mesh.slotOf(dense.classes[c]);
    if (slot < 0) throw std::logic_error("dense evidence: a channel's class has no slot in the mesh");
    channel_slot_.push_back(static_cast<std::size_t>(slot));
    slot_channel_[static_cast<std::size_t>(slot)] = c;
  }
}

float DenseEvidence::read(int u, int v, float h_m, const Eigen::Vector3f* normal, float* out, float* scratch) const {
  const std::size_t n = channels();
  float* q = scratch;
  float* l = scratch + n;
  prior_.likelihoods(h_m, normal, l);
  const std::uint8_t* p = dense_.at(u, v);
  float sum = 0.0f;
  for (std::size_t c = 0; c < n; ++c) sum += (q[c] = static_cast<float>(p[c]) * l[c]);
  if (!(sum > 0.0f)) {  // every channel quantised to 0 (cannot sum to 1): no opinion
    for (std::size_t c = 0; c < n; ++c) q[c] = 1.0f;
    sum = static_cast<float>(n);
  }
  const float k = 1.0f / sum;
  float top = 0.0f;
  for (std::size_t c = 0; c < n; ++c) top = std::max(top, q[c] *= k);
  for (std::size_t s = 0; s < slot_channel_.size(); ++s) out[s] = q[slot_channel_[s]];
  // A slot with no channel copied "none"; renormalise so that the slots sum to 1.
  if (channel_slot_.size() != slot_channel_.size()) {
    float total = 0.0f;
    for (std::size_t s = 0; s < slot_channel_.size(); ++s) total += out[s];
    for (std::size_t s = 0; s < slot_channel_.size(); ++s) out[s] /= total;
  }
  return top;
}

}  // namespace artemis::mapping
