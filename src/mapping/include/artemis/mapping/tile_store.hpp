#pragma once
// Tiles: the map cut into square columns of a fixed edge (in whole blocks of VoxelMap), so that a
// long drive's memory stays bounded. A tile the sensor and every view still waiting for stage 2
// have left by more than evict_distance_m is finished: the mapper writes what the final mesh needs
// of it to a tile file and drops it from memory (Mapper::evictTiles). Returns that later fall in a
// finished tile are dropped and counted; a finished tile that the drive comes back to (within
// reloadDistanceM()) is loaded again from its state file, whole, and goes on being mapped.
//
// A tile file holds the tile's vertices (those whose voxel lies in it) with their uid
// (SemanticMesh::uid), position, normal, colour, class, confidence and class distribution, and the
// faces its voxels own. A face corner is a vertex of the tile (its index in the file) or, across a
// tile border, a vertex of another tile named by that tile and its uid (an "external"): the final
// mesh.ply is the tiles stitched by those names (pipeline/tiled_mesh.cpp), without seams.

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/status.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_key.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::mapping {

struct TileParams {
  bool enabled = true;
  // Edge of a tile, rounded to whole blocks (VoxelMap::kBlockVoxels voxels, 6.4 m at 0.4 m), one
  // at least.
  double edge_m = 25.6;
  // A tile is finished once it is farther than this (horizontally) from the sensor and from every
  // view stage 2 still holds. It must exceed stage 2's reach (RefinementParams::max_range_m) and
  // should exceed the LiDAR's, whose returns beyond it into finished tiles are dropped.
  double evict_distance_m = 120.0;
  // Frames between two looks for finished tiles. Finishing a tile meshes what is pending in it (the
  // work finish() does for the whole map) and renumbers what stays in memory: a look that finds
  // tiles costs a few hundred ms on 2 cores, so looks are rare (on the simulated street at 17 m/s,
  // one frame in 50, and the p95 of the frame time stays what it was).
  int check_every = 50;
};

// A tile's column: the floor of voxel x and y over the tile's edge in voxels.
struct TileKey {
  std::int32_t x = 0;
  std::int32_t y = 0;
  friend bool operator==(const TileKey&, const TileKey&) = default;
  friend auto operator<=>(const TileKey&, const TileKey&) = default;
};

// One tile as written.
struct TileContents {
  TileKey key;
  std::vector<std::uint64_t> uids;  // ascending
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::array<std::uint8_t, 3>> rgb;  // 8-bit sRGB of the colour mean, where coloured
  std::vector<std::uint8_t> coloured;            // 1 where a view coloured the vertex
  std::vector<semantics::ClassId> classes;
  std::vector<float> confidence;
  std::vector<semantics::ClassId> slots;  // the mesh's semantic slots when written
  std::vector<float> distribution;        // vertex-major, slots.size() per vertex; empty without classes
  // A corner below kExternal is an index into this tile's vertices; kExternal + i names externals[i].
  static constexpr std::uint32_t kExternal = 0x80000000u;
  std::vector<Face> faces;
  struct External {
    TileKey tile;
    std::uint64_t uid = 0;
  };
  std::vector<External> externals;
};

Status writeTileFile(const std::filesystem::path& path, const TileContents& tile);
Result<TileContents> readTileFile(const std::filesystem::path& path);

// Where finished tiles go, and which went.
class TileStore {
 public:
  // Throws std::invalid_argument for an edge or a distance that is not > 0.
  TileStore(const TileParams& params, double voxel_size_m);

  [[nodiscard]] const TileParams& params() const { return params_; }
  [[nodiscard]] bool enabled() const { return params_.enabled && !directory_.empty(); }
  // Tile files go here (created when the first is written); empty: tiles stay in memory.
  void setDirectory(const std::filesystem::path& directory) { directory_ = directory; }
  [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }

  [[nodiscard]] TileKey tileOf(const VoxelKey& voxel) const;
  // Horizontal distance from p_W to the tile's square (0 inside).
  [[nodiscard]] double distance(const TileKey& tile, const Eigen::Vector3f& p_W) const;
  // The tile's file as last written, and its state file (Mapper::reloadTiles) beside it. Each time
  // a tile is written it gets new files (its generation, in their names), so that a run resumed
  // from a checkpoint taken before the drive came back to the tile and wrote it again still finds
  // the files that checkpoint knows. The outputs name the last ones tile_X_Y.bin (outputName).
  [[nodiscard]] std::filesystem::path fileOf(const TileKey& tile) const;
  [[nodiscard]] std::filesystem::path stateFileOf(const TileKey& tile) const;
  [[nodiscard]] static std::string outputName(const TileKey& tile);
  // The tile's edge (m), whole blocks.
  [[nodiscard]] double edgeM() const { return edge_voxels_ * voxel_size_m_; }
  // A finished tile is loaded again once the sensor comes within this distance (m) of it: one tile
  // edge nearer than the eviction distance, so that a tile on the edge does not leave and come back
  // at every look.
  [[nodiscard]] double reloadDistanceM() const { return params_.evict_distance_m - edgeM(); }
  // The voxel of the tile nearest to `voxel` (itself when it lies in the tile).
  [[nodiscard]] VoxelKey clampInto(const TileKey& tile, const VoxelKey& voxel) const;

  [[nodiscard]] bool finished(const TileKey& tile) const { return finished_.contains(tile); }
  [[nodiscard]] bool anyFinished() const { return !finished_.empty(); }
  // Whether a finished tile lies within `distance` (horizontally) of p_W.
  [[nodiscard]] bool anyFinishedWithin(const Eigen::Vector3f& p_W, double distance) const;
  [[nodiscard]] const std::set<TileKey>& finishedTiles() const { return finished_; }
  // Writes the tile's file (atomically) and counts the tile finished.
  // With `state` (the bytes of a state file), writes that first.
  Status write(const TileContents& tile, std::span<const std::span<const std::byte>> state = {});
  // The drive came back: the tile is in memory again (its files stay until it is written again).
  void reopen(const TileKey& tile) { finished_.erase(tile); }

  // Checkpoints: which tiles are finished (their files are checked to exist on load).
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  TileParams params_;
  std::int32_t edge_voxels_;
  double voxel_size_m_;
  std::filesystem::path directory_;
  std::set<TileKey> finished_;
  std::map<TileKey, std::uint32_t> generation_;  // how many times each tile was written
  [[nodiscard]] std::filesystem::path fileOf(const TileKey& tile, std::uint32_t generation, const char* kind) const;
};

}  // namespace artemis::mapping
