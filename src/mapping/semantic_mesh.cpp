#include "artemis/mapping/semantic_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace artemis::mapping {

void SemanticMesh::growVertexRoom() {
  // A vector of a million vertices that doubles copies itself into memory it touches for the first
  // time: on KITTI 0013 the frame that crossed 2^20 vertices took 230 ms to insert instead of 20.
  // Room for kVertexRoom vertices is reserved at once instead (address space: pages are only paid
  // for when written), for every per-vertex array, so that none of them reallocates before then.
  const std::size_t room = std::max(kVertexRoom, 2 * positions_.capacity());
  const std::size_t slots = slots_.size();
  positions_.reserve(room);
  measured_.reserve(room);
  normals_.reserve(room);
  voxels_.reserve(room);
  views_.reserve(room);
  uids_.reserve(room);
  voxel_index_.reserve(room);
  semantic_weight_.reserve(room);
  refined_weight_.reserve(room);
  colour_mean_.reserve(room);
  colour_var_.reserve(room);
  if (slots > 1) {
    evidence_.reserve(room * slots);
    log_likelihood_.reserve(room * slots);
  }
}

std::uint32_t SemanticMesh::addVertex(const Eigen::Vector3f& p_W, const VoxelKey& voxel,
                                      const Eigen::Vector3f& to_sensor, std::uint32_t voxel_index) {
  if (positions_.size() == positions_.capacity()) growVertexRoom();
  positions_.push_back(p_W);
  measured_.push_back(p_W);
  voxel_index_.push_back(voxel_index);
  normals_.push_back(to_sensor);  // until the voxel's plane gives a better one
  voxels_.push_back(voxel);
  views_.push_back(to_sensor);
  uids_.push_back(next_uid_++);
  return static_cast<std::uint32_t>(positions_.size() - 1);
}

std::size_t SemanticMesh::addSemanticClass(semantics::ClassId cls) {
  if (const int s = slotOf(cls); s >= 0) return static_cast<std::size_t>(s);
  const std::size_t old_slots = slots_.size();
  slots_.push_back(cls);
  // Re-lay the evidence out with the new slot empty: once per new class, O(vertices).
  const auto relayout = [&](std::vector<float>& evidence, std::size_t n) {
    std::vector<float> out(n * slots_.size(), 0.0f);
    for (std::size_t i = 0; i < n; ++i) std::copy_n(&evidence[i * old_slots], old_slots, &out[i * slots_.size()]);
    evidence = std::move(out);
  };
  relayout(evidence_, semantic_weight_.size());
  relayout(voxel_evidence_, voxel_weight_.size());
  // Views so far saw the new class as "none of the prompted classes": it starts with slot 0's lambda.
  relayout(log_likelihood_, refined_weight_.size());
  for (std::size_t i = 0; i < refined_weight_.size(); ++i) {
    log_likelihood_[i * slots_.size() + old_slots] = log_likelihood_[i * slots_.size()];
  }
  return slots_.size() - 1;
}

int SemanticMesh::slotOf(semantics::ClassId cls) const {
  const auto it = std::find(slots_.begin(), slots_.end(), cls);
  return it == slots_.end() ? -1 : static_cast<int>(it - slots_.begin());
}

void SemanticMesh::observe(std::uint32_t v, std::size_t slot, float w) {
  if (v >= semantic_weight_.size()) {
    // Vertices are born in order; grow in steps so that a frame's new vertices cost one resize.
    const std::size_t n = std::max<std::size_t>(v + 1, positions_.size());
    semantic_weight_.resize(n, 0.0f);
    evidence_.resize(n * slots_.size(), 0.0f);
  }
  evidence_[static_cast<std::size_t>(v) * slots_.size() + slot] += w;
  semantic_weight_[v] += w;
  const std::uint32_t voxel = voxel_index_[v];
  if (voxel == kNoVoxel) return;
  if (voxel >= voxel_weight_.size()) {
    const std::size_t n = std::max<std::size_t>(voxel + 1, 2 * voxel_weight_.size());
    voxel_weight_.resize(n, 0.0f);
    voxel_evidence_.resize(n * slots_.size(), 0.0f);
  }
  voxel_evidence_[static_cast<std::size_t>(voxel) * slots_.size() + slot] += w;
  voxel_weight_[voxel] += w;
}

float SemanticMesh::voxelSemanticWeight(std::uint32_t v) const {
  const std::uint32_t voxel = voxel_index_[v];
  return voxel < voxel_weight_.size() ? voxel_weight_[voxel] : 0.0f;
}

void SemanticMesh::observeDistribution(std::uint32_t v, const float* p, float w) {
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    if (p[s] > 0.0f) observe(v, s, w * p[s]);
  }
}

void SemanticMesh::reserveRefinement() {
  refined_weight_.resize(positions_.size(), 0.0f);
  log_likelihood_.resize(positions_.size() * slots_.size(), 0.0f);
}

void SemanticMesh::addLogLikelihood(std::uint32_t v, std::size_t hit_slot, float log_hit, float log_miss, float w) {
  float* lambda = &log_likelihood_[static_cast<std::size_t>(v) * slots_.size()];
  for (std::size_t s = 0; s < slots_.size(); ++s) lambda[s] += w * (s == hit_slot ? log_hit : log_miss);
  refined_weight_[v] += w;
}

void SemanticMesh::addLogLikelihoods(std::uint32_t v, const float* log_p, float w) {
  float* lambda = &log_likelihood_[static_cast<std::size_t>(v) * slots_.size()];
  for (std::size_t s = 0; s < slots_.size(); ++s) lambda[s] += w * log_p[s];
  refined_weight_[v] += w;
}

bool SemanticMesh::distribution(std::uint32_t v, float* out) const {
  const std::size_t n = slots_.size();
  std::fill_n(out, n, 0.0f);
  const float w_cell = semanticWeight(v);
  const float w_voxel = voxelSemanticWeight(v);
  const bool refined = refinedWeight(v) > 0.0f;
  if (!(w_cell > 0.0f) && !(w_voxel > 0.0f)) {
    if (!refined) return false;
    std::fill_n(out, n, 1.0f / static_cast<float>(n));  // a flat prior
  } else {
    stageOne(v, w_cell, w_voxel, out);
  }
  if (!refined) return true;
  // Softmax of lambda + log(prior).
  const float* lambda = &log_likelihood_[static_cast<std::size_t>(v) * n];
  float top = -std::numeric_limits<float>::infinity();
  for (std::size_t s = 0; s < n; ++s) {
    out[s] = lambda[s] + stage_one_weight_ * std::log(std::max(out[s], kStageOneFloor));
    top = std::max(top, out[s]);
  }
  float sum = 0.0f;
  for (std::size_t s = 0; s < n; ++s) sum += (out[s] = std::exp(out[s] - top));
  for (std::size_t s = 0; s < n; ++s) out[s] /= sum;
  return true;
}

void SemanticMesh::stageOne(std::uint32_t v, float w_cell, float w_voxel, float* out) const {
  const std::size_t n = slots_.size();
  float sum = 0.0f;
  if (w_cell > 0.0f) {
    const float* e = &evidence_[static_cast<std::size_t>(v) * n];
    for (std::size_t s = 0; s < n; ++s) out[s] = e[s];
    sum = w_cell;
  }
  if (w_voxel > 0.0f) {
    const float* e = &voxel_evidence_[static_cast<std::size_t>(voxel_index_[v]) * n];
    const float k = voxel_prior_ / w_voxel;
    for (std::size_t s = 0; s < n; ++s) out[s] += k * e[s];
    sum += voxel_prior_;
  }
  for (std::size_t s = 0; s < n; ++s) out[s] /= sum;
}

semantics::ClassId SemanticMesh::vertexClass(std::uint32_t v) const {
  constexpr std::size_t kMaxSlots = 256;
  std::array<float, kMaxSlots> p{};
  if (!distribution(v, p.data())) return semantics::kNoClass;
  std::size_t best = 0;
  for (std::size_t s = 1; s < slots_.size(); ++s) {
    if (p[s] > p[best]) best = s;
  }
  return slots_[best];
}

float SemanticMesh::confidence(std::uint32_t v, double lambda) const {
  return static_cast<float>(1.0 - std::exp(-lambda * static_cast<double>(voxelSemanticWeight(v))));
}

std::vector<ByteRange> SemanticMesh::roomAhead(std::size_t count) const {
  // The colours catch up with the vertices when the next view is fused (reserveColours).
  const std::size_t colours = count + positions_.size() - std::min(positions_.size(), colour_mean_.size());
  return {artemis::roomAhead(positions_, count),   artemis::roomAhead(measured_, count),
          artemis::roomAhead(normals_, count),     artemis::roomAhead(voxels_, count),
          artemis::roomAhead(views_, count),       artemis::roomAhead(uids_, count),
          artemis::roomAhead(voxel_index_, count), artemis::roomAhead(colour_mean_, colours),
          artemis::roomAhead(colour_var_, colours)};
}

void SemanticMesh::reserveColours(std::size_t count) {
  if (colour_mean_.size() < count) colour_mean_.resize(count, Eigen::Vector3f::Zero());
  if (colour_var_.size() < count) colour_var_.resize(count, Eigen::Vector3f::Zero());
}

void SemanticMesh::fuseColour(std::uint32_t v, const Eigen::Vector3f& c, float variance) {
  if (v >= colour_var_.size()) reserveColours();
  Eigen::Vector3f& mean = colour_mean_[v];
  Eigen::Vector3f& var = colour_var_[v];
  if (!(var.x() > 0.0f)) {
    mean = c;
    var.setConstant(variance);
    return;
  }
  for (int k = 0; k < 3; ++k) {
    const float gain = var(k) / (var(k) + variance);
    mean(k) += gain * (c(k) - mean(k));
    var(k) *= 1.0f - gain;
  }
}

void SemanticMesh::setVoxelFaces(const VoxelKey& voxel, std::vector<Face> faces) {
  auto& slot = faces_[voxel];
  changes_.faces_removed += slot.size();
  changes_.faces_added += faces.size();
  face_count_ = face_count_ - slot.size() + faces.size();
  changes_.voxels.push_back(voxel);
  slot = std::move(faces);
}

const std::vector<Face>* SemanticMesh::voxelFaces(const VoxelKey& voxel) const {
  const auto it = faces_.find(voxel);
  return it == faces_.end() ? nullptr : &it->second;
}

std::vector<Face> SemanticMesh::faces() const {
  std::vector<VoxelKey> keys;
  keys.reserve(faces_.size());
  for (const auto& [key, faces] : faces_) {
    if (!faces.empty()) keys.push_back(key);
  }
  std::sort(keys.begin(), keys.end());
  std::vector<Face> out;
  out.reserve(face_count_);
  for (const VoxelKey& key : keys) {
    const auto& faces = faces_.at(key);
    out.insert(out.end(), faces.begin(), faces.end());
  }
  return out;
}

std::vector<VoxelKey> SemanticMesh::faceOwners() const {
  std::vector<VoxelKey> keys;
  keys.reserve(faces_.size());
  for (const auto& [key, faces] : faces_) {
    if (!faces.empty()) keys.push_back(key);
  }
  return keys;
}

void SemanticMesh::dropVoxelFaces(const VoxelKey& voxel) {
  const auto it = faces_.find(voxel);
  if (it == faces_.end()) return;
  face_count_ -= it->second.size();
  faces_.erase(it);
}

namespace {

// Moves the kept items of `a` (stride values per item, item i kept where new_id[i] is not kGone)
// down to their new places; `a` may hold fewer items than new_id (arrays grown on demand).
template <typename T>
void keepItems(std::vector<T>& a, const std::vector<std::uint32_t>& new_id, std::size_t stride = 1) {
  const std::size_t n = std::min(a.size() / stride, new_id.size());
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (new_id[i] == SemanticMesh::kGone) continue;
    if (kept != i) std::copy_n(a.begin() + static_cast<std::ptrdiff_t>(i * stride), stride,
                               a.begin() + static_cast<std::ptrdiff_t>(kept * stride));
    ++kept;
  }
  a.resize(kept * stride);
}

}  // namespace

void SemanticMesh::compactVertices(const std::vector<std::uint32_t>& new_id,
                                   const std::vector<std::uint32_t>& voxel_new_id) {
  if (new_id.size() != positions_.size()) {
    throw std::invalid_argument("SemanticMesh::compactVertices: " + std::to_string(new_id.size()) + " ids for " +
                                std::to_string(positions_.size()) + " vertices");
  }
  const std::size_t slots = slots_.size();
  keepItems(positions_, new_id);
  keepItems(measured_, new_id);
  keepItems(normals_, new_id);
  keepItems(voxels_, new_id);
  keepItems(views_, new_id);
  keepItems(uids_, new_id);
  keepItems(voxel_index_, new_id);
  keepItems(semantic_weight_, new_id);
  keepItems(evidence_, new_id, slots);
  keepItems(refined_weight_, new_id);
  keepItems(log_likelihood_, new_id, slots);
  keepItems(colour_mean_, new_id);
  keepItems(colour_var_, new_id);
  for (std::uint32_t& voxel : voxel_index_) {
    voxel = voxel < voxel_new_id.size() ? voxel_new_id[voxel] : kNoVoxel;  // kGone is kNoVoxel
  }
  keepItems(voxel_weight_, voxel_new_id);
  keepItems(voxel_evidence_, voxel_new_id, slots);
  for (auto& [key, faces] : faces_) {
    for (Face& f : faces) {
      for (std::uint32_t& v : f) {
        if (new_id[v] == kGone) throw std::logic_error("SemanticMesh::compactVertices: a face uses a vertex that goes");
        v = new_id[v];
      }
    }
  }
}

SemanticMesh::Compact SemanticMesh::compact() const {
  Compact c;
  c.faces = faces();
  constexpr std::uint32_t kUnused = 0xFFFFFFFFu;
  std::vector<std::uint32_t> new_id(positions_.size(), kUnused);
  for (Face& f : c.faces) {
    for (std::uint32_t& v : f) {
      if (new_id[v] == kUnused) {
        new_id[v] = static_cast<std::uint32_t>(c.vertex_ids.size());
        c.vertex_ids.push_back(v);
      }
      v = new_id[v];
    }
  }
  return c;
}

}  // namespace artemis::mapping
