// A finished tile's whole state, for when the drive comes back to it (tile_store.hpp): every value
// the voxel map and the mesh hold of its voxels and vertices, written as they are and read back
// into other indices. Mapper::reloadTiles (tile_reload.cpp) puts the pieces together.

#include <algorithm>
#include <string>

#include "artemis/core/archive.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_map.hpp"
#include "voxel_archive.hpp"

namespace artemis::mapping {

namespace {

// The values of items `ids` of `a` (`stride` values an item); zeros for items past its end (arrays
// that grow on demand).
// Zero of a number, an Eigen vector or a plain struct.
template <typename T>
T zeroOf() {
  if constexpr (requires { T::Zero(); }) {
    return T::Zero();
  } else {
    return T{};
  }
}

template <typename T>
std::vector<T> pick(const std::vector<T>& a, const std::vector<std::uint32_t>& ids, std::size_t stride = 1) {
  std::vector<T> out(ids.size() * stride, zeroOf<T>());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::size_t at = static_cast<std::size_t>(ids[i]) * stride;
    if (at + stride <= a.size()) std::copy_n(a.begin() + static_cast<std::ptrdiff_t>(at), stride, &out[i * stride]);
  }
  return out;
}

template <typename T>
std::vector<T> readArray(ArchiveReader& in, std::size_t expected, const char* what) {
  std::vector<T> a;
  in.array(a);
  if (a.size() != expected) {
    in.fail(std::string("a tile state's ") + what + " has " + std::to_string(a.size()) + " values, not " +
            std::to_string(expected));
  }
  return a;
}

bool anyNonZero(const std::vector<float>& a) {
  return std::any_of(a.begin(), a.end(), [](float x) { return x != 0.0f; });
}

// One item's per-slot values `from` (in a file's slots) into `to` (this mesh's `slots`): slot s of
// the file is slot_of[s] here; slots the file lacks get 0.
void scatterSlots(const float* from, const std::vector<std::size_t>& slot_of, float* to, std::size_t slots) {
  std::fill_n(to, slots, 0.0f);
  for (std::size_t s = 0; s < slot_of.size(); ++s) to[slot_of[s]] += from[s];
}

}  // namespace

std::vector<std::size_t> SemanticMesh::readSlots(ArchiveReader& in) {
  std::vector<semantics::ClassId> file_slots;
  in.array(file_slots);
  if (file_slots.empty() || file_slots.size() > 256) in.fail("a tile state has no semantic slots, or too many");
  std::vector<std::size_t> slot_of(file_slots.size());
  for (std::size_t s = 0; s < file_slots.size(); ++s) slot_of[s] = addSemanticClass(file_slots[s]);
  return slot_of;
}

void SemanticMesh::saveVertices(ArchiveWriter& out, const std::vector<std::uint32_t>& ids) const {
  const std::size_t slots = slots_.size();
  out.section("vertices");
  out.array(slots_);
  out.array(pick(uids_, ids));
  out.array(pick(positions_, ids));
  out.array(pick(measured_, ids));
  out.array(pick(normals_, ids));
  out.array(pick(voxels_, ids));
  out.array(pick(views_, ids));
  out.array(pick(colour_mean_, ids));
  out.array(pick(colour_var_, ids));
  out.array(pick(semantic_weight_, ids));
  out.array(pick(evidence_, ids, slots));
  out.array(pick(refined_weight_, ids));
  out.array(pick(log_likelihood_, ids, slots));
}

std::vector<std::uint32_t> SemanticMesh::loadVertices(ArchiveReader& in,
                                                      const std::function<std::uint32_t(std::uint64_t)>& existing) {
  in.section("vertices");
  const std::vector<std::size_t> slot_of = readSlots(in);
  std::vector<std::uint64_t> uids;
  in.array(uids);
  const std::size_t n = uids.size();
  const std::size_t fs = slot_of.size();
  const auto positions = readArray<Eigen::Vector3f>(in, n, "positions");
  const auto measured = readArray<Eigen::Vector3f>(in, n, "measured positions");
  const auto normals = readArray<Eigen::Vector3f>(in, n, "normals");
  const auto voxels = readArray<VoxelKey>(in, n, "voxel keys");
  const auto views = readArray<Eigen::Vector3f>(in, n, "view directions");
  const auto colour_mean = readArray<Eigen::Vector3f>(in, n, "colours");
  const auto colour_var = readArray<Eigen::Vector3f>(in, n, "colour variances");
  const auto semantic_weight = readArray<float>(in, n, "semantic weights");
  const auto evidence = readArray<float>(in, n * fs, "class evidence");
  const auto refined_weight = readArray<float>(in, n, "refined weights");
  const auto log_likelihood = readArray<float>(in, n * fs, "class log-likelihoods");
  for (const std::uint64_t uid : uids) {
    if (uid >= next_uid_) in.fail("a tile state names vertex " + std::to_string(uid) + ", never added");
  }

  std::vector<std::uint32_t> ids(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t v = existing ? existing(uids[i]) : kGone;
    if (v == kGone) {
      if (positions_.size() == positions_.capacity()) growVertexRoom();
      v = static_cast<std::uint32_t>(positions_.size());
      positions_.emplace_back();
      measured_.emplace_back();
      normals_.emplace_back();
      voxels_.emplace_back();
      views_.emplace_back();
      uids_.emplace_back();
      voxel_index_.push_back(kNoVoxel);
    } else if (v >= positions_.size() || uids_[v] != uids[i]) {
      in.fail("a tile state's vertex " + std::to_string(uids[i]) + " was matched to another vertex in memory");
    }
    ids[i] = v;
    positions_[v] = positions[i];
    measured_[v] = measured[i];
    normals_[v] = normals[i];
    voxels_[v] = voxels[i];
    views_[v] = views[i];
    uids_[v] = uids[i];
    voxel_index_[v] = kNoVoxel;
  }
  // The arrays that grow on demand grow to every vertex where the tile brings values, and are
  // overwritten wherever they reach (a merged vertex's values in memory were the same or older).
  const std::size_t total = positions_.size();
  const std::size_t slots = slots_.size();
  const bool coloured =
      std::any_of(colour_var.begin(), colour_var.end(), [](const Eigen::Vector3f& c) { return c.x() > 0.0f; });
  if (coloured || !colour_var_.empty()) reserveColours();
  if (anyNonZero(semantic_weight)) {
    semantic_weight_.resize(total, 0.0f);
    evidence_.resize(total * slots, 0.0f);
  }
  if (anyNonZero(refined_weight)) reserveRefinement();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t v = ids[i];
    if (v < colour_var_.size()) {
      colour_mean_[v] = colour_mean[i];
      colour_var_[v] = colour_var[i];
    }
    if (v < semantic_weight_.size()) {
      semantic_weight_[v] = semantic_weight[i];
      scatterSlots(&evidence[i * fs], slot_of, &evidence_[static_cast<std::size_t>(v) * slots], slots);
    }
    if (v < refined_weight_.size()) {
      refined_weight_[v] = refined_weight[i];
      scatterSlots(&log_likelihood[i * fs], slot_of, &log_likelihood_[static_cast<std::size_t>(v) * slots], slots);
    }
  }
  return ids;
}

void SemanticMesh::saveVoxelSemantics(ArchiveWriter& out, const std::vector<std::uint32_t>& voxels) const {
  out.section("voxel-semantics");
  out.array(slots_);
  out.array(pick(voxel_weight_, voxels));
  out.array(pick(voxel_evidence_, voxels, slots_.size()));
}

void SemanticMesh::loadVoxelSemantics(ArchiveReader& in, const std::vector<std::uint32_t>& voxels) {
  in.section("voxel-semantics");
  const std::vector<std::size_t> slot_of = readSlots(in);
  const std::size_t fs = slot_of.size();
  const auto weight = readArray<float>(in, voxels.size(), "voxel semantic weights");
  const auto evidence = readArray<float>(in, voxels.size() * fs, "voxel class evidence");
  if (!anyNonZero(weight)) return;
  const std::size_t slots = slots_.size();
  const std::uint32_t top = *std::max_element(voxels.begin(), voxels.end());
  if (top >= voxel_weight_.size()) {
    voxel_weight_.resize(top + 1, 0.0f);
    voxel_evidence_.resize((static_cast<std::size_t>(top) + 1) * slots, 0.0f);
  }
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    voxel_weight_[voxels[i]] = weight[i];
    scatterSlots(&evidence[i * fs], slot_of, &voxel_evidence_[static_cast<std::size_t>(voxels[i]) * slots], slots);
  }
}

std::uint32_t SemanticMesh::addGhost(const Eigen::Vector3f& p_W, const Eigen::Vector3f& normal, const VoxelKey& voxel,
                                     std::uint64_t uid, const Eigen::Vector3f* colour) {
  const std::uint32_t v = addVertex(p_W, voxel, normal, kNoVoxel);
  --next_uid_;  // addVertex numbered it as new
  uids_[v] = uid;
  if (colour != nullptr) {
    reserveColours();
    colour_mean_[v] = *colour;
    colour_var_[v].setConstant(1e-3f);
  }
  return v;
}

void SemanticMesh::addChanges(const Changes& more) {
  changes_.voxels.insert(changes_.voxels.end(), more.voxels.begin(), more.voxels.end());
  changes_.faces_added += more.faces_added;
  changes_.faces_removed += more.faces_removed;
}

void VoxelMap::saveVoxels(ArchiveWriter& out, const std::vector<std::uint32_t>& indices,
                          const std::unordered_map<std::uint32_t, std::uint32_t>& local) const {
  out.section("voxels");
  out.value(static_cast<std::uint64_t>(indices.size()));
  std::vector<std::uint32_t> vertices;
  for (const std::uint32_t index : indices) {
    const Voxel& v = voxels_[index];
    out.value(keys_[index]);
    vertices.clear();
    for (const std::uint32_t id : v.vertices) vertices.push_back(local.at(id));
    out.array(vertices);
    detail::saveVoxelFields(out, v);
  }
}

std::vector<std::uint32_t> VoxelMap::loadVoxels(ArchiveReader& in, const std::vector<std::uint32_t>& ids) {
  in.section("voxels");
  const auto count = in.value<std::uint64_t>();
  if (count > in.remaining()) in.fail("a tile state's voxel count runs past its end");
  std::vector<std::uint32_t> indices;
  indices.reserve(static_cast<std::size_t>(count));
  for (std::uint64_t k = 0; k < count; ++k) {
    const auto key = in.value<VoxelKey>();
    Voxel v;
    in.array(v.vertices);
    detail::loadVoxelFields(in, v);
    for (std::uint32_t& id : v.vertices) {
      if (id >= ids.size()) in.fail("a tile state's voxel names a vertex the tile does not have");
      id = ids[id];
    }
    if (indexOf(key) != kNoVertex) in.fail("a tile state's voxel is already in memory");
    const std::uint32_t index = findOrAdd(key, hashOf(key));
    voxels_[index] = std::move(v);
    indices.push_back(index);
  }
  return indices;
}

}  // namespace artemis::mapping
