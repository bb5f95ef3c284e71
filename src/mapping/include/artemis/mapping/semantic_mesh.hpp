#pragma once
// The Living Map's mesh: vertices (the points the voxel map kept) with their normal, voxel of
// origin and viewing direction, and faces grouped by the voxel that owns them, so that re-meshing
// a voxel replaces exactly its faces. A change log says which voxels changed in the current frame
// (for the viewer and incremental exports). Later stages add per-vertex colour and class
// distributions beside these arrays.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "artemis/mapping/voxel_key.hpp"

namespace artemis::mapping {

using Face = std::array<std::uint32_t, 3>;

class SemanticMesh {
 public:
  // Vertices, structure of arrays; index = vertex id.
  [[nodiscard]] std::size_t vertexCount() const { return positions_.size(); }
  [[nodiscard]] const std::vector<Eigen::Vector3f>& positions() const { return positions_; }
  [[nodiscard]] const std::vector<Eigen::Vector3f>& normals() const { return normals_; }
  [[nodiscard]] const std::vector<VoxelKey>& voxels() const { return voxels_; }
  // Unit direction from the vertex towards the sensor that first saw it.
  [[nodiscard]] const std::vector<Eigen::Vector3f>& viewDirections() const { return views_; }

  std::uint32_t addVertex(const Eigen::Vector3f& p_W, const VoxelKey& voxel, const Eigen::Vector3f& to_sensor);
  void setNormal(std::uint32_t vertex, const Eigen::Vector3f& normal) { normals_[vertex] = normal; }

  // Replaces the faces owned by `voxel` and logs the change.
  void setVoxelFaces(const VoxelKey& voxel, std::vector<Face> faces);
  [[nodiscard]] const std::vector<Face>* voxelFaces(const VoxelKey& voxel) const;
  [[nodiscard]] std::size_t faceCount() const { return face_count_; }
  // Every face, voxel by voxel in key order (deterministic).
  [[nodiscard]] std::vector<Face> faces() const;

  // The frame's change log: voxels whose faces were replaced, and face counts added and removed.
  struct Changes {
    std::vector<VoxelKey> voxels;
    std::size_t faces_added = 0;
    std::size_t faces_removed = 0;
  };
  void beginFrame() { changes_ = {}; }
  [[nodiscard]] const Changes& changes() const { return changes_; }

  // Vertices used by at least one face, and the faces renumbered onto them: what exporters write.
  struct Compact {
    std::vector<std::uint32_t> vertex_ids;  // into this mesh's arrays
    std::vector<Face> faces;                // indices into vertex_ids
  };
  [[nodiscard]] Compact compact() const;

 private:
  std::vector<Eigen::Vector3f> positions_;
  std::vector<Eigen::Vector3f> normals_;
  std::vector<VoxelKey> voxels_;
  std::vector<Eigen::Vector3f> views_;
  std::unordered_map<VoxelKey, std::vector<Face>, VoxelKeyHash> faces_;
  std::size_t face_count_ = 0;
  Changes changes_;
};

}  // namespace artemis::mapping
