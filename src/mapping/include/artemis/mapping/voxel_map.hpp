#pragma once
// A hashed voxel grid of the points the mesh is built from. Each voxel keeps at most one point per
// sub-cell (subdivisions^3 sub-cells), so that scans of the same surface do not pile up: the
// minimum spacing of kept points is voxel_size / subdivisions. Kept points become mesh vertices.
// Inserting a scan returns the voxels that received new points: the frame's active set.
// insert() spreads its per-point arithmetic over the calling TBB arena; results do not depend on
// the thread count.

#include <array>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/prefault.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_key.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::mapping {

struct VoxelMapParams {
  double voxel_size_m = 0.4;  // as ImMesh
  // Sub-cells per axis (1..8). 4 keeps points 0.1 m apart: on the simulated street F1 at 0.1 m was
  // the same as with 8 (0.05 m), with a third of the faces and half the meshing time.
  int subdivisions = 4;
};

// The frames whose returns fell in a point's sub-cell (saturating), the frames whose rays passed
// through it, the last frame that hit it, and how many frames lie between its first hit and its last
// (saturating; in what would be the struct's padding).
struct PointEvidence {
  std::uint32_t last_hit = 0;
  std::uint8_t hits = 0;
  std::uint8_t misses = 0;
  std::uint16_t span = 0;
};

struct Voxel {
  std::vector<std::uint32_t> vertices;   // mesh vertex ids of the kept points
  std::vector<Eigen::Vector3f> points;   // their positions, kept here too for cache-friendly meshing
  std::vector<std::uint16_t> sub_cells;  // their sub-cells (x * n + y) * n + z
  // Free-space evidence per kept point (see FreeSpaceCarver), one vector rather than three: most
  // voxels hold a few points, and each vector costs a header and an allocation per voxel.
  std::vector<PointEvidence> evidence;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());  // bounds of points
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  std::array<std::uint64_t, 8> occupied{};  // one bit per sub-cell (8^3 = 512)
  std::uint32_t points_when_meshed = 0;     // vertices.size() when last meshed
  std::uint32_t active_frame = 0;           // the last insert() that added a point here
  std::uint32_t hit_frame = 0;              // the last insert() with a return here
  std::uint32_t carved_frame = 0;           // the last insert() after which faces here lost carved points
  // The plane of the points when last meshed (unit normal), zero when they were fewer than the
  // mesher needs, on a line or scattered: what FreeSpaceCarver tests crossings against.
  Eigen::Vector3f plane_normal = Eigen::Vector3f::Zero();
  std::uint32_t plane_points = 0;  // how many points the plane was fitted to
  std::uint32_t meshed_frame = 0;  // the insert() count when it was last meshed
};

// Asks the caches for voxel v's fields, ahead of a loop's use of them (a hint; loops over voxels
// scattered in memory are bound by their fetches).
inline void prefetch(const Voxel& v) {
  const auto* bytes = reinterpret_cast<const char*>(&v);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  for (std::size_t line = 0; line < sizeof(Voxel); line += 64) __builtin_prefetch(bytes + line);
}

class VoxelMap {
 public:
  explicit VoxelMap(const VoxelMapParams& params);

  // Adds world-frame points seen from `sensor_W`; kept points are added to `mesh` as vertices.
  // Points with a non-zero entry in `drop` (one per point, when given) are left out without being
  // counted as refused. Returns the keys of voxels that gained points, in order of first gain
  // (deterministic).
  std::vector<VoxelKey> insert(const std::vector<Eigen::Vector3f>& points_W, const Eigen::Vector3f& sensor_W,
                               SemanticMesh& mesh, const std::vector<std::uint8_t>* drop = nullptr);
  // The vertex holding the sub-cell of point i of the last insert() (the point itself, or the one
  // that was there before), or kNoVertex for a refused point. Valid until the next insert().
  [[nodiscard]] std::uint32_t insertedVertex(std::size_t i) const;
  static constexpr std::uint32_t kNoVertex = std::numeric_limits<std::uint32_t>::max();
  // Removes the points of voxel `index` whose entry in `remove` (one per point) is non-zero: their
  // sub-cells become free and their vertices leave the voxel (they stay in the mesh's arrays,
  // unused, until the faces that use them are re-meshed). Appends the removed vertex ids to
  // `removed`. The caller re-meshes the voxel and its neighbours.
  void removePoints(std::uint32_t index, const std::vector<std::uint8_t>& remove, std::vector<std::uint32_t>& removed);
  // Tiles leaving memory: removes the voxels with gone[i] != 0 from the map (their keys, blocks and
  // points; their vertices are the mesh's to drop), the others keeping their order. Returns each
  // old index's new one (kNoVertex for a removed voxel). Forgets the last insert() (insertedVertex).
  std::vector<std::uint32_t> removeVoxels(const std::vector<std::uint8_t>& gone);
  // Renumbers the vertices the voxels hold after SemanticMesh::compactVertices(new_id).
  void renumberVertices(const std::vector<std::uint32_t>& new_id);
  // Index of voxel `key` in voxelAt(), or kNoVertex.
  [[nodiscard]] std::uint32_t indexOf(const VoxelKey& key) const;
  // The vertex holding the sub-cell of world point p_W, or kNoVertex where the map has none.
  [[nodiscard]] std::uint32_t vertexAt(const Eigen::Vector3f& p_W) const;

  [[nodiscard]] const Voxel* find(const VoxelKey& key) const;
  Voxel* find(const VoxelKey& key);
  [[nodiscard]] VoxelKey keyOf(const Eigen::Vector3f& p_W) const { return voxelKeyOf(p_W, inv_voxel_size_); }
  [[nodiscard]] std::size_t size() const { return voxels_.size(); }
  // The room reserved past the voxels' end for `count` more (populatePages).
  [[nodiscard]] std::vector<ByteRange> roomAhead(std::size_t count) const {
    return {artemis::roomAhead(voxels_, count), artemis::roomAhead(keys_, count)};
  }
  // Points refused so far: not finite, or farther than 1000 km from the origin.
  [[nodiscard]] std::size_t rejectedPoints() const { return rejected_; }
  [[nodiscard]] const VoxelMapParams& params() const { return params_; }
  [[nodiscard]] float voxelSize() const { return static_cast<float>(params_.voxel_size_m); }
  [[nodiscard]] std::uint32_t frame() const { return frame_; }
  // Keys of every voxel, sorted.
  [[nodiscard]] std::vector<VoxelKey> keys() const;
  [[nodiscard]] const VoxelKey& keyAt(std::uint32_t index) const { return keys_[index]; }
  [[nodiscard]] const Voxel& voxelAt(std::uint32_t index) const { return voxels_[index]; }
  Voxel& voxelAt(std::uint32_t index) { return voxels_[index]; }

  // Voxels grouped in blocks of kBlockVoxels^3, for culling: a view first tests blocks, then the
  // voxels of the blocks it sees. Each block: its key (voxel key / kBlockVoxels, floored) and the
  // indices of its voxels in creation order.
  static constexpr int kBlockVoxels = 16;
  struct Block {
    VoxelKey key;
    std::vector<std::uint32_t> voxels;
  };
  [[nodiscard]] const std::vector<Block>& blocks() const { return blocks_; }

  // Tiles coming back (tile_state.cpp): voxels `indices` whole, their vertices written as
  // local.at(id); loadVoxels adds them back, local vertex i as ids[i], and returns their new
  // indices. Throws ArchiveError on damage, or for a voxel the map already has.
  void saveVoxels(ArchiveWriter& out, const std::vector<std::uint32_t>& indices,
                  const std::unordered_map<std::uint32_t, std::uint32_t>& local) const;
  std::vector<std::uint32_t> loadVoxels(ArchiveReader& in, const std::vector<std::uint32_t>& ids);

  // Checkpoints (mapping/checkpoint.cpp): the whole map, its per-frame scratch aside; load() into a
  // map made with the same params (checked).
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  // Open addressing with linear probing over a power-of-two table of indices into voxels_: the
  // 27 lookups per meshed voxel made std::unordered_map's bucket chasing the mesher's top cost.
  static std::uint64_t hashOf(const VoxelKey& key);
  [[nodiscard]] std::size_t slotOf(const VoxelKey& key) const;
  std::uint32_t findOrAdd(const VoxelKey& key, std::uint64_t hash);
  // Sub-cell of p_W within voxel `key`, clamped against rounding at the voxel's far faces.
  [[nodiscard]] int subCellOf(const Eigen::Vector3f& p_W, const VoxelKey& key) const;
  void grow();
  // Fills table_ (of its present size) and the blocks from keys_.
  void reindex();
  // Fetches into the caches, ahead of insert()'s use: the hash slots, voxels and point arrays of
  // the points a little after point i of the frame.
  void prefetchAhead(std::size_t i) const;
  // Counts this frame as a hit of the point holding `sub_cell` in v (once per frame).
  void countHit(Voxel& v, std::uint16_t sub_cell) const;

  VoxelMapParams params_;
  float inv_voxel_size_;
  float inv_sub_size_;
  static constexpr std::size_t kVoxelRoom = std::size_t{1} << 20;
  std::vector<Voxel> voxels_;
  std::vector<VoxelKey> keys_;        // key of voxels_[i]
  std::vector<std::uint32_t> table_;  // voxel index + 1; 0 = empty slot
  std::uint32_t frame_ = 0;
  std::size_t rejected_ = 0;
  struct Prepared {
    VoxelKey key;
    std::uint64_t hash = 0;
    int sub_cell = -1;        // -1: point refused, -2: dropped by the caller
    std::uint32_t voxel = 0;  // index into voxels_, once inserted
  };
  std::vector<Prepared> prepared_;  // per-frame scratch of insert()
  std::vector<Block> blocks_;
  std::unordered_map<VoxelKey, std::uint32_t, VoxelKeyHash> block_of_;  // block key -> index into blocks_
};

}  // namespace artemis::mapping
