// The mapper's tiles (tile_store.hpp): finding the tiles the drive has left, writing them, and
// dropping them from memory.

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "artemis/core/archive.hpp"
#include "artemis/core/colour.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/mapping/mapper.hpp"

namespace artemis::mapping {

namespace {

VoxelKey blockCorner(const VoxelKey& block) {
  return {block.x * VoxelMap::kBlockVoxels, block.y * VoxelMap::kBlockVoxels, block.z * VoxelMap::kBlockVoxels};
}

}  // namespace

std::size_t Mapper::dropInFinishedTiles(const std::vector<Eigen::Vector3f>& points_W) {
  std::size_t dropped = 0;
  TileKey last{std::numeric_limits<std::int32_t>::min(), 0};
  bool last_finished = false;
  for (std::size_t i = 0; i < points_W.size(); ++i) {
    // insert() refuses (and counts) what has no voxel key.
    const Eigen::Vector3f& p = points_W[i];
    if (drop_[i] != 0 || !p.allFinite() || !(p.cwiseAbs().maxCoeff() < 1e6f)) continue;
    // By the voxel the point would go to, as the tiles' voxels are sorted (never a new voxel in a
    // finished tile).
    const TileKey t = tiles_.tileOf(map_.keyOf(p));
    if (!(t == last)) {  // successive returns mostly share a tile
      last = t;
      last_finished = tiles_.finished(t);
    }
    if (last_finished) {
      drop_[i] = 2;
      ++dropped;
    }
  }
  return dropped;
}

std::set<TileKey> Mapper::leftTiles(const std::vector<Eigen::Vector3f>& keep_near, std::size_t* in_memory) const {
  std::set<TileKey> far;
  std::set<TileKey> near;
  if (tiles_.enabled()) {
    const double reach = params_.tiles.evict_distance_m;
    for (const VoxelMap::Block& b : map_.blocks()) {
      const TileKey t = tiles_.tileOf(blockCorner(b.key));
      if (far.contains(t) || near.contains(t)) continue;
      const bool left = std::all_of(keep_near.begin(), keep_near.end(),
                                    [&](const Eigen::Vector3f& p) { return tiles_.distance(t, p) > reach; });
      (left ? far : near).insert(t);
    }
  }
  if (in_memory != nullptr) *in_memory = far.size() + near.size();
  return far;
}

std::vector<VoxelKey> Mapper::voxelsOf(const std::set<TileKey>& tiles, std::vector<std::uint8_t>* gone) const {
  std::vector<VoxelKey> keys;
  if (gone != nullptr) gone->assign(map_.size(), 0);
  for (const VoxelMap::Block& b : map_.blocks()) {
    if (!tiles.contains(tiles_.tileOf(blockCorner(b.key)))) continue;
    for (const std::uint32_t index : b.voxels) {
      if (gone != nullptr) (*gone)[index] = 1;
      keys.push_back(map_.keyAt(index));
    }
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

Result<EvictionStats> Mapper::evictTiles(const std::vector<Eigen::Vector3f>& keep_near) {
  completeHandedOver();
  std::size_t in_memory = 0;
  const std::set<TileKey> far = leftTiles(keep_near, &in_memory);
  Stopwatch clock;
  const std::size_t meshed = closeTiles(far);
  const double close_ms = clock.elapsedMs();
  auto stats = dropTiles(far);
  if (!stats) return stats;
  stats->tiles_in_memory = in_memory - far.size();
  stats->meshed_voxels = meshed;
  stats->close_ms = close_ms;
  stats->ms += close_ms;
  return stats;
}

Result<EvictionStats> Mapper::dropTiles(const std::set<TileKey>& far) {
  completeHandedOver();
  EvictionStats stats;
  if (far.empty()) return stats;
  Stopwatch clock;
  std::vector<std::uint8_t> gone;
  stats.voxels = voxelsOf(far, &gone).size();
  if (Status s = writeTiles(far, stats.faces, true); !s.isOk()) return s;
  stats.write_ms = clock.elapsedMs();
  Stopwatch step;
  stats.tiles = far.size();
  dropFinished(gone, stats);
  stats.drop_ms = step.elapsedMs();
  stats.ms = clock.elapsedMs();
  return stats;
}

std::size_t Mapper::closeTiles(const std::set<TileKey>& far) {
  completeHandedOver();
  if (far.empty()) return 0;
  const std::vector<VoxelKey> keys = voxelsOf(far, nullptr);
  // The voxels in memory just across the border: meshed later, they would miss the points of the
  // tiles that left (their rim), and the faces along the border with them.
  std::vector<VoxelKey> ring;
  std::set<VoxelKey> seen(keys.begin(), keys.end());
  for (const VoxelKey& k : keys) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const VoxelKey n{k.x + dx, k.y + dy, k.z + dz};
          if (!far.contains(tiles_.tileOf(n)) && map_.find(n) != nullptr && seen.insert(n).second) ring.push_back(n);
        }
      }
    }
  }
  // What finish() would do: mesh what is pending there, then close the small holes, with the faces
  // across the border as context (a hole along the border is not the tile's outline). Only fills
  // of the leaving tiles' own vertices are kept: the ring's outer edge, cut from what lies beyond,
  // shows loops that are no holes (faces farther out close them), and a hole across the border,
  // seen again once the other side leaves without this side's faces, would be closed twice.
  std::vector<VoxelKey> pending = pendingAmong(keys);
  const std::vector<VoxelKey> pending_ring = pendingAmong(ring);
  pending.insert(pending.end(), pending_ring.begin(), pending_ring.end());
  meshInChunks(pending);
  std::vector<Face> context;
  for (const std::vector<VoxelKey>* group : {&keys, static_cast<const std::vector<VoxelKey>*>(&ring)}) {
    for (const VoxelKey& k : *group) {
      if (const std::vector<Face>* f = mesh_.voxelFaces(k)) context.insert(context.end(), f->begin(), f->end());
    }
  }
  fillHoles(context, [&](const Face& f) { return cornersIn(f, far); });
  return pending.size();
}

bool Mapper::cornersIn(const Face& f, const std::set<TileKey>& tiles, bool outside) const {
  return std::all_of(f.begin(), f.end(),
                     [&](std::uint32_t v) { return tiles.contains(tiles_.tileOf(mesh_.voxels()[v])) != outside; });
}

Result<std::size_t> Mapper::writeRemainingTiles() {
  completeHandedOver();
  if (!tiles_.enabled()) return std::size_t{0};
  std::set<TileKey> live;
  for (const VoxelKey& k : mesh_.voxels()) {
    if (const TileKey t = tiles_.tileOf(k); !tiles_.finished(t)) live.insert(t);
  }
  for (const VoxelKey& k : mesh_.faceOwners()) {
    if (const TileKey t = tiles_.tileOf(k); !tiles_.finished(t)) live.insert(t);
  }
  std::size_t faces = 0;
  if (Status s = writeTiles(live, faces, false); !s.isOk()) return s;
  return live.size();
}

Status Mapper::writeTiles(const std::set<TileKey>& tiles, std::size_t& faces, bool with_state) {
  // Each tile's vertices by uid (ids ascend with uids, but for those of tiles loaded back, added
  // at the end) and the voxels owning its faces.
  std::map<TileKey, std::vector<std::uint32_t>> members;
  const std::vector<VoxelKey>& vertex_voxels = mesh_.voxels();
  for (std::uint32_t v = 0; v < vertex_voxels.size(); ++v) {
    if (const TileKey t = tiles_.tileOf(vertex_voxels[v]); tiles.contains(t)) members[t].push_back(v);
  }
  for (auto& [tile, ids] : members) {
    std::sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) { return mesh_.uid(a) < mesh_.uid(b); });
  }
  std::map<TileKey, std::vector<VoxelKey>> owners;
  for (const VoxelKey& k : mesh_.faceOwners()) {
    if (const TileKey t = tiles_.tileOf(k); tiles.contains(t)) owners[t].push_back(k);
  }
  for (const TileKey& t : tiles) {
    std::vector<VoxelKey>& own = owners[t];
    std::sort(own.begin(), own.end());
    const TileContents contents = tileContents(t, members[t], own);
    faces += contents.faces.size();
    ArchiveWriter head;
    ArchiveWriter body;
    if (with_state) tileState(t, members[t], own, contents, head, body);
    const std::array<std::span<const std::byte>, 2> parts{head.bytes(), body.bytes()};
    if (Status s = tiles_.write(contents, with_state ? std::span<const std::span<const std::byte>>(parts)
                                                     : std::span<const std::span<const std::byte>>());
        !s.isOk()) {
      return s;
    }
  }
  return Status::ok();
}

TileContents Mapper::tileContents(const TileKey& tile, const std::vector<std::uint32_t>& members,
                                  const std::vector<VoxelKey>& owners) const {
  TileContents c;
  c.key = tile;
  const std::size_t n = members.size();
  const std::size_t slots = mesh_.slotCount();
  const bool classes = slots > 1;
  c.uids.resize(n);
  c.positions.resize(n);
  c.normals.resize(n);
  c.rgb.assign(n, {128, 128, 128});
  c.coloured.assign(n, 0);
  c.classes.assign(n, semantics::kNoClass);
  c.confidence.assign(n, 0.0f);
  if (classes) {
    c.slots = mesh_.semanticSlots();
    c.distribution.assign(n * slots, 0.0f);
  }
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  local.reserve(n);
  const double lambda = params_.semantics.confidence_lambda;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t v = members[i];
    local.emplace(v, static_cast<std::uint32_t>(i));
    c.uids[i] = mesh_.uid(v);
    c.positions[i] = mesh_.positions()[v];
    c.normals[i] = mesh_.normals()[v];
    if (mesh_.hasColour(v)) {
      c.coloured[i] = 1;
      const Eigen::Vector3f m = mesh_.colourMean(v);
      for (int k = 0; k < 3; ++k) {
        c.rgb[i][static_cast<std::size_t>(k)] =
            static_cast<std::uint8_t>(std::lround(255.0 * srgbEncode(static_cast<double>(m(k)))));
      }
    }
    if (classes) {
      c.classes[i] = mesh_.vertexClass(v);
      c.confidence[i] = mesh_.confidence(v, lambda);
      mesh_.distribution(v, &c.distribution[i * slots]);
    }
  }
  std::map<std::pair<TileKey, std::uint64_t>, std::uint32_t> external_of;
  for (const VoxelKey& owner : owners) {
    for (const Face& f : *mesh_.voxelFaces(owner)) {
      Face out{};
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t v = f[k];
        if (const auto it = local.find(v); it != local.end()) {
          out[k] = it->second;
          continue;
        }
        const TileContents::External e{tiles_.tileOf(mesh_.voxels()[v]), mesh_.uid(v)};
        const auto [at, added] =
            external_of.try_emplace({e.tile, e.uid}, static_cast<std::uint32_t>(c.externals.size()));
        if (added) c.externals.push_back(e);
        out[k] = TileContents::kExternal + at->second;
      }
      c.faces.push_back(out);
    }
  }
  return c;
}

void Mapper::dropFinished(const std::vector<std::uint8_t>& gone, EvictionStats& stats) {
  for (const VoxelKey& k : mesh_.faceOwners()) {
    if (tiles_.finished(tiles_.tileOf(k))) mesh_.dropVoxelFaces(k);
  }
  // A vertex stays while its tile is in memory, or while a face in memory uses it (a face of a
  // tile in memory across the border): the tile file holds it as it is now, and nothing changes
  // it any more, since no view or scan reaches that far.
  const std::size_t n = mesh_.vertexCount();
  std::vector<std::uint8_t> used(n, 0);
  for (const VoxelKey& k : mesh_.faceOwners()) {
    for (const Face& f : *mesh_.voxelFaces(k)) {
      for (const std::uint32_t v : f) used[v] = 1;
    }
  }
  stats.new_id.assign(n, SemanticMesh::kGone);
  std::uint32_t next = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (used[v] != 0 || !tiles_.finished(tiles_.tileOf(mesh_.voxels()[v]))) stats.new_id[v] = next++;
  }
  stats.vertices = n - next;
  const std::vector<std::uint32_t> voxel_new_id = map_.removeVoxels(gone);
  mesh_.compactVertices(stats.new_id, voxel_new_id);
  map_.renumberVertices(stats.new_id);
}

}  // namespace artemis::mapping
