#pragma once
// What the browser viewer shows, held by the server: the mesh cut into cubic blocks, each with a
// version, so that a page that has version V fetches only the blocks changed since V (during a run
// that is the blocks the last frames touched, not the map); the trajectory; the classes and the
// run's status (frame counter, per-stage timings).
//
// Blocks on the wire (GET /api/blocks?since=V), little endian, every section 4-byte aligned so
// the page reads them as typed arrays without copying:
//   header  u32 magic "ARTB" (0x42545241), u32 format (1), u32 version, u32 block count
//   block   i32 bx, by, bz, u32 vertices n, u32 indices m,
//           f32 xyz[3n], u8 rgb[3n] (sRGB texture; grey where none), u8 class[n] (vocabulary id,
//           0: none), u32 indices[m] (into this block's vertices)
// A block with n = 0 was removed. Faces belong to the block of their first vertex; vertices
// shared with a face of another block appear in both.

#include <array>
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "artemis/core/status.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_key.hpp"

namespace artemis::viewer {

using BlockKey = mapping::VoxelKey;

struct Block {
  std::vector<float> xyz;
  std::vector<std::uint8_t> rgb;
  std::vector<std::uint8_t> classes;
  std::vector<std::uint32_t> indices;
  [[nodiscard]] std::size_t vertexCount() const { return classes.size(); }
};

inline constexpr std::uint32_t kBlocksMagic = 0x42545241;  // "ARTB"
inline constexpr std::uint32_t kBlocksFormat = 1;

class Scene {
 public:
  Scene() = default;
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // Replaces the given blocks (an empty block removes one) as one new version.
  void update(std::vector<std::pair<BlockKey, Block>> blocks);
  // Moves the blocks `keep_in_memory` refuses to disk (an unnamed temporary file, gone with the
  // process), unchanged and with their versions: a long run's viewer then holds in memory only
  // what may still change (the map's tiles in memory), and serves the rest from disk. Returns
  // how many it moved; an error names the file problem (the blocks then stay in memory).
  template <typename Keep>
  Result<std::size_t> spillIf(Keep&& keep_in_memory);
  [[nodiscard]] std::size_t blocksOnDisk() const;
  // The blocks changed after version `since`, encoded as above (all blocks for since = 0).
  [[nodiscard]] std::string encodeSince(std::uint32_t since) const;
  [[nodiscard]] std::uint32_t version() const;

  // Status and metadata (JSON objects shown by the page): replaced as a whole.
  void setInfo(const std::string& key, nlohmann::json value);
  void appendTrajectory(const Eigen::Vector3d& position_W);
  // {"version", "vertices", "faces", "blocks", "trajectory": [[x,y,z]...], <info keys>...}.
  [[nodiscard]] nlohmann::json infoJson() const;

 private:
  struct Entry {
    Block block;
    std::uint32_t version = 0;
    // On disk: the block's encoding (as encodeSince writes it) at this offset of spill_.
    bool spilled = false;
    std::uint64_t offset = 0;
    std::uint32_t bytes = 0;
    std::uint32_t spilled_vertices = 0;
    std::uint32_t spilled_faces = 0;
    [[nodiscard]] std::size_t vertexCount() const { return spilled ? spilled_vertices : block.vertexCount(); }
  };
  // Writes e's block to the spill file and frees it.
  Status spill(const BlockKey& key, Entry& e);
  std::FILE* spill_ = nullptr;
  std::uint64_t spill_size_ = 0;
  mutable std::mutex mutex_;
  std::map<BlockKey, Entry> blocks_;  // removed blocks stay as empty entries (tombstones)
  std::uint32_t version_ = 0;
  std::size_t vertices_ = 0;
  std::size_t faces_ = 0;
  nlohmann::json info_ = nlohmann::json::object();
  std::vector<std::array<float, 3>> trajectory_;
};

template <typename Keep>
Result<std::size_t> Scene::spillIf(Keep&& keep_in_memory) {
  std::lock_guard lock(mutex_);
  std::size_t moved = 0;
  for (auto& [key, e] : blocks_) {
    if (e.spilled || e.block.vertexCount() == 0 || keep_in_memory(key)) continue;
    if (Status s = spill(key, e); !s.isOk()) return s;
    ++moved;
  }
  return moved;
}

// A mesh as blocks of `block_size_m`: what `artemis view` serves for a finished run.
// `rgb` and `classes` may be empty.
std::vector<std::pair<BlockKey, Block>> meshBlocks(std::span<const Eigen::Vector3f> positions,
                                                   std::span<const std::array<std::uint32_t, 3>> triangles,
                                                   std::span<const std::array<std::uint8_t, 3>> rgb,
                                                   std::span<const std::uint8_t> classes, double block_size_m);

// Blocks of a live mapper's mesh: block B holds the faces of the voxels whose coarserKey(voxel,
// block_voxels) is B. `blocks` are the ones to (re)build.
std::vector<std::pair<BlockKey, Block>> liveBlocks(const mapping::SemanticMesh& mesh, std::span<const BlockKey> blocks,
                                                   std::int32_t block_voxels);

}  // namespace artemis::viewer
