#include "artemis/mapping/semantic_mesh.hpp"

#include <algorithm>

namespace artemis::mapping {

std::uint32_t SemanticMesh::addVertex(const Eigen::Vector3f& p_W, const VoxelKey& voxel,
                                      const Eigen::Vector3f& to_sensor) {
  positions_.push_back(p_W);
  normals_.push_back(to_sensor);  // until the voxel's plane gives a better one
  voxels_.push_back(voxel);
  views_.push_back(to_sensor);
  return static_cast<std::uint32_t>(positions_.size() - 1);
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
