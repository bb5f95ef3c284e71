// The mapper's tiles when the drive comes back (tile_store.hpp): each finished tile's state file,
// written as it left, and loading it back, stitched to what stayed in memory by vertex uid.

#include <algorithm>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>

#include "artemis/core/archive.hpp"
#include "artemis/core/colour.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/mapping/mapper.hpp"
#include "checked_file.hpp"

namespace artemis::mapping {

namespace {

constexpr const char* kStateMagic = "ARTEMIS tile state";
constexpr std::uint32_t kStateVersion = 1;

// What a state file's faces section holds.
struct StateFaces {
  std::vector<VoxelKey> owners;
  std::vector<std::uint32_t> counts;  // faces per owner
  std::vector<Face> faces;            // corners as TileContents numbers them, local ones as ids once loaded
  std::vector<TileContents::External> externals;
};

using UidIndex = std::unordered_map<std::uint64_t, std::uint32_t>;  // vertex uid -> id in memory

// The vertices in memory that tiles' vertices or faces may name, by uid: those in the tiles
// (kept there for faces across their borders) and in the tiles around them (a face reaches one
// voxel beyond its owner).
UidIndex verticesAround(const std::set<TileKey>& tiles, const SemanticMesh& mesh, const TileStore& store) {
  std::set<TileKey> around;
  for (const TileKey& t : tiles) {
    for (std::int32_t dx = -1; dx <= 1; ++dx) {
      for (std::int32_t dy = -1; dy <= 1; ++dy) around.insert({t.x + dx, t.y + dy});
    }
  }
  UidIndex index;
  TileKey last{std::numeric_limits<std::int32_t>::min(), 0};
  bool last_around = false;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    if (const TileKey t = store.tileOf(mesh.voxels()[v]); !(t == last)) {
      last = t;
      last_around = around.contains(t);
    }
    if (last_around) index.emplace(mesh.uid(v), v);
  }
  return index;
}

// Reads a state file's faces section; their local corners become the tile's vertex ids.
StateFaces readFaces(ArchiveReader& in, const std::vector<std::uint32_t>& ids) {
  in.section("faces");
  StateFaces sf;
  in.array(sf.owners);
  in.array(sf.counts);
  in.array(sf.faces);
  in.array(sf.externals);
  std::uint64_t total = 0;
  for (const std::uint32_t c : sf.counts) total += c;
  if (sf.counts.size() != sf.owners.size() || total != sf.faces.size() || !in.atEnd()) {
    in.fail("the tile state's faces do not match their owners");
  }
  for (Face& face : sf.faces) {
    for (std::uint32_t& c : face) {
      if (c >= TileContents::kExternal) {
        if (c - TileContents::kExternal >= sf.externals.size()) in.fail("a face names an external it lacks");
      } else if (c >= ids.size()) {
        in.fail("a face names a vertex the tile lacks");
      } else {
        c = ids[c];
      }
    }
  }
  return sf;
}

// The vertices of finished tiles that faces coming back name across their borders: loaded from
// those tiles' files (position, normal, colour) for as long as a face uses them.
class Ghosts {
 public:
  Ghosts(SemanticMesh& mesh, const VoxelMap& map, const TileStore& store, UidIndex& in_memory)
      : mesh_(mesh), map_(map), store_(store), in_memory_(in_memory) {}

  // The vertex an external corner names (kGone: no tile holds it any more).
  std::uint32_t of(const TileContents::External& e) {
    if (const auto it = in_memory_.find(e.uid); it != in_memory_.end()) return it->second;
    if (!store_.finished(e.tile)) return SemanticMesh::kGone;
    auto& n = files_[e.tile];
    if (!n) {
      auto read = readTileFile(store_.fileOf(e.tile));
      n = read ? std::move(*read) : TileContents{};
    }
    const auto at = std::lower_bound(n->uids.begin(), n->uids.end(), e.uid);
    if (at == n->uids.end() || *at != e.uid) return SemanticMesh::kGone;
    const auto i = static_cast<std::size_t>(at - n->uids.begin());
    Eigen::Vector3f colour;
    for (int c = 0; c < 3; ++c) {
      colour(c) = static_cast<float>(srgbDecode(n->rgb[i][static_cast<std::size_t>(c)] / 255.0));
    }
    const VoxelKey voxel = store_.clampInto(e.tile, map_.keyOf(n->positions[i]));
    const std::uint32_t v =
        mesh_.addGhost(n->positions[i], n->normals[i], voxel, e.uid, n->coloured[i] != 0 ? &colour : nullptr);
    in_memory_[e.uid] = v;
    ++added_;
    return v;
  }
  [[nodiscard]] std::size_t added() const { return added_; }

 private:
  SemanticMesh& mesh_;
  const VoxelMap& map_;
  const TileStore& store_;
  UidIndex& in_memory_;
  std::map<TileKey, std::optional<TileContents>> files_;
  std::size_t added_ = 0;
};

// Loads one tile's vertices (merged with those `in_memory` holds of it), voxels and voxel
// semantics from its state file; returns its faces. Throws ArchiveError.
StateFaces loadTileState(ArchiveReader& in, const TileKey& tile, SemanticMesh& mesh, VoxelMap& map, UidIndex& in_memory,
                         ReloadStats& stats) {
  in.section("tile-state");
  if (!(in.value<TileKey>() == tile)) in.fail("the tile state is of another tile");
  std::size_t merged = 0;
  const std::vector<std::uint32_t> ids = mesh.loadVertices(in, [&](std::uint64_t uid) {
    const auto it = in_memory.find(uid);
    if (it == in_memory.end()) return SemanticMesh::kGone;
    ++merged;
    return it->second;
  });
  for (const std::uint32_t v : ids) in_memory[mesh.uid(v)] = v;
  const std::vector<std::uint32_t> voxels = map.loadVoxels(in, ids);
  for (const std::uint32_t index : voxels) {
    for (const std::uint32_t v : map.voxelAt(index).vertices) mesh.setVoxelIndex(v, index);
  }
  mesh.loadVoxelSemantics(in, voxels);
  stats.vertices += ids.size();
  stats.merged += merged;
  stats.voxels += voxels.size();
  return readFaces(in, ids);
}

// Gives a tile's faces back to their owners, their corners across borders resolved by `ghosts`;
// a face naming a vertex no tile holds any more is left out (counted).
void restoreFaces(const StateFaces& sf, Ghosts& ghosts, SemanticMesh& mesh, ReloadStats& stats) {
  std::vector<std::uint32_t> external_id(sf.externals.size());
  for (std::size_t i = 0; i < sf.externals.size(); ++i) external_id[i] = ghosts.of(sf.externals[i]);
  std::size_t at = 0;
  for (std::size_t o = 0; o < sf.owners.size(); ++o) {
    std::vector<Face> owned;
    for (std::uint32_t j = 0; j < sf.counts[o]; ++j, ++at) {
      Face f = sf.faces[at];
      bool whole = true;
      for (std::uint32_t& c : f) {
        if (c >= TileContents::kExternal) c = external_id[c - TileContents::kExternal];
        whole = whole && c != SemanticMesh::kGone;
      }
      if (whole) {
        owned.push_back(f);
      } else {
        ++stats.faces_dropped;
      }
    }
    stats.faces += owned.size();
    if (!owned.empty()) mesh.setVoxelFaces(sf.owners[o], std::move(owned));
  }
}

}  // namespace

void Mapper::tileState(const TileKey& tile, const std::vector<std::uint32_t>& members,
                       const std::vector<VoxelKey>& owners, const TileContents& contents, ArchiveWriter& head,
                       ArchiveWriter& body) const {
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  local.reserve(members.size());
  for (std::size_t i = 0; i < members.size(); ++i) local.emplace(members[i], static_cast<std::uint32_t>(i));
  std::vector<std::uint32_t> voxels;
  for (const VoxelKey& k : voxelsOf({tile}, nullptr)) voxels.push_back(map_.indexOf(k));
  body.section("tile-state");
  body.value(tile);
  mesh_.saveVertices(body, members);
  map_.saveVoxels(body, voxels, local);
  mesh_.saveVoxelSemantics(body, voxels);
  body.section("faces");
  std::vector<std::uint32_t> counts;
  counts.reserve(owners.size());
  for (const VoxelKey& k : owners) counts.push_back(static_cast<std::uint32_t>(mesh_.voxelFaces(k)->size()));
  body.array(owners);
  body.array(counts);
  body.array(contents.faces);
  body.array(contents.externals);
  detail::writeCheckedHeader(head, kStateMagic, kStateVersion, body);
}

std::set<TileKey> Mapper::returnedTiles(const Eigen::Vector3f& sensor_W) const {
  std::set<TileKey> back;
  if (!tiles_.enabled() || !sensor_W.allFinite()) return back;
  const double reach = tiles_.reloadDistanceM();
  for (const TileKey& t : tiles_.finishedTiles()) {
    if (tiles_.distance(t, sensor_W) < reach) back.insert(t);
  }
  return back;
}

Result<ReloadStats> Mapper::reloadTiles(const std::set<TileKey>& tiles) {
  completeHandedOver();
  ReloadStats stats;
  if (tiles.empty()) return stats;
  Stopwatch clock;
  std::vector<detail::CheckedFile> files;
  for (const TileKey& t : tiles) {
    auto f = detail::readCheckedFile(tiles_.stateFileOf(t), kStateMagic, kStateVersion, "tile state");
    if (!f) return f.status();
    files.push_back(std::move(*f));
  }
  UidIndex in_memory = verticesAround(tiles, mesh_, tiles_);
  const std::size_t changes_before = mesh_.changes().voxels.size();
  // Every tile's voxels and vertices first, then the faces: a face across a border between two
  // tiles coming back names a vertex of the other.
  std::vector<StateFaces> faces;
  try {
    auto tile = tiles.begin();
    for (std::size_t k = 0; k < files.size(); ++k, ++tile) {
      ArchiveReader in(files[k].bodyBytes(), tiles_.stateFileOf(*tile).string());
      faces.push_back(loadTileState(in, *tile, mesh_, map_, in_memory, stats));
    }
  } catch (const ArchiveError& e) {
    return parseError(e.what());
  }
  Ghosts ghosts(mesh_, map_, tiles_, in_memory);
  for (const StateFaces& sf : faces) restoreFaces(sf, ghosts, mesh_, stats);
  stats.ghosts = ghosts.added();
  for (const TileKey& t : tiles) tiles_.reopen(t);
  const SemanticMesh::Changes& now = mesh_.changes();
  reloaded_.voxels.insert(reloaded_.voxels.end(), now.voxels.begin() + static_cast<std::ptrdiff_t>(changes_before),
                          now.voxels.end());
  reloaded_.faces_added += stats.faces;
  stats.tiles = tiles.size();
  stats.ms = clock.elapsedMs();
  return stats;
}

}  // namespace artemis::mapping
