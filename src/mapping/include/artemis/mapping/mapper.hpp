#pragma once
// Stage 1 of the Living Map, geometry part: each frame's points go into the voxel map (1a) and the
// voxels that changed enough are re-meshed (1c), in parallel over voxels. Re-meshing is deferred
// for a voxel until its points have grown by `remesh_growth` since it was last meshed, so that a
// voxel gaining a point or two per scan is not re-triangulated every frame; finish() meshes every
// voxel still pending. Results do not depend on the thread count.

#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <set>
#include <span>

#include "artemis/core/heap_prefaulter.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/mapping/free_space.hpp"
#include "artemis/mapping/hole_filling.hpp"
#include "artemis/mapping/incremental_mesher.hpp"
#include "artemis/mapping/refinement.hpp"
#include "artemis/mapping/semantic_constraint.hpp"
#include "artemis/mapping/semantic_fusion.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/swept_volume.hpp"
#include "artemis/mapping/tile_store.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::mapping {

struct MapperParams {
  VoxelMapParams voxels;
  MesherParams mesher;
  SemanticFusionParams semantics;
  RefinementParams refinement;
  SemanticConstraintParams constraint;
  FreeSpaceParams free_space;
  HoleFillParams holes;  // finish() closes the mesh's small holes
  TileParams tiles;      // finished tiles leave memory (once setTileDirectory names where to)
  // A voxel is first meshed once it holds first_mesh_points, then re-meshed once its points grew
  // by remesh_growth (and by at least remesh_min_new) since it was last meshed; finish() meshes
  // whatever is still pending, so the final mesh does not depend on these. On KITTI drive 0013
  // (2 cores) growth 1.5 and 12 points cut the meshing stage from ~21 to ~17 ms a frame, against
  // growth 1.0 and 10 points; the cost is that sparse far voxels join the live mesh later.
  double remesh_growth = 1.5;
  int remesh_min_new = 3;
  int first_mesh_points = 12;
  int threads = 0;  // 0: all cores
  // The vehicle's body in the LiDAR frame (empty: none). Returns inside it at the frame's pose or
  // any earlier one are dropped (see SweptVolume): the vehicle drove through that space.
  Eigen::AlignedBox3f vehicle_box_L;
};

struct FrameStats {
  double insert_ms = 0.0;
  double mesh_ms = 0.0;
  double fuse_ms = 0.0;                      // semantic fusion (1b), when the frame came with an observation
  double constrain_ms = 0.0;                 // semantic constraint (1d): cutting faces and moving vertices
  double carve_ms = 0.0;                     // free space: counting misses and removing what was seen through
  double stage_two_wait_ms = 0.0;            // after carving, for stage 2 work handed over (Mapper::handOver)
  double beside_constraint_wait_ms = 0.0;    // after the constraint, for the work beside it (besideNextConstraint)
  std::size_t points = 0;                    // points given
  std::size_t points_kept = 0;               // new mesh vertices
  std::size_t points_in_vehicle_path = 0;    // dropped: inside the vehicle's box at this or an earlier pose
  std::size_t points_in_finished_tiles = 0;  // dropped: in a tile already written (TileStore)
  std::size_t points_carved = 0;             // kept points removed as free space (rays and vehicle box)
  std::size_t points_tested_free = 0;        // kept points tested against rays for free space
  std::size_t active_voxels = 0;             // voxels that gained points
  std::size_t meshed_voxels = 0;             // voxels re-meshed this frame
  std::size_t semantic_observations = 0;
  std::size_t faces_cut = 0;   // faces the semantic constraint cut (1d)
  ConstraintStats constraint;  // the semantic constraint's patch, solve and times (1d)
};

// What Mapper::evictTiles did.
struct EvictionStats {
  std::size_t tiles = 0;            // tiles written and dropped from memory
  std::size_t tiles_in_memory = 0;  // the others
  std::size_t voxels = 0;           // their voxels
  std::size_t vertices = 0;         // vertices dropped from memory
  std::size_t faces = 0;            // faces written
  std::size_t meshed_voxels = 0;    // voxels meshed before writing (pending, as finish() would)
  double ms = 0.0;
  double close_ms = 0.0;  // meshing and closing holes before they leave
  double write_ms = 0.0;  // the tile files
  double drop_ms = 0.0;   // renumbering what stays
  // Old vertex id -> new (SemanticMesh::kGone for a vertex that left); empty when nothing left.
  std::vector<std::uint32_t> new_id;
};

// What loading finished tiles back cost and brought (Mapper::reloadTiles).
struct ReloadStats {
  std::size_t tiles = 0;
  std::size_t voxels = 0;
  std::size_t vertices = 0;       // loaded, merged ones included
  std::size_t merged = 0;         // of them, vertices a face in memory had kept there
  std::size_t faces = 0;          // faces back in memory
  std::size_t ghosts = 0;         // vertices of finished tiles across their borders, loaded for those faces
  std::size_t faces_dropped = 0;  // faces naming a vertex no tile holds any more (carved since)
  double ms = 0.0;
};

// A frame's segmented camera view, for semantic fusion.
struct SemanticInput {
  const CameraView* view = nullptr;
  const semantics::SemanticObservation* observation = nullptr;
  const semantics::Vocabulary* vocabulary = nullptr;  // names the classes (nullptr: SemanticKITTI's)
};

class Mapper {
 public:
  explicit Mapper(const MapperParams& params);
  ~Mapper();
  Mapper(const Mapper&) = delete;
  Mapper& operator=(const Mapper&) = delete;

  // With `semantic`, the observation is fused into the cells of the frame's points (1b) after they
  // are inserted (1a) and before meshing (1c).
  FrameStats integrate(const PointCloud& points_L, const Isometry3d& T_W_L, const SemanticInput* semantic = nullptr);
  // 1b for an observation that arrives after its frame was integrated (a segmenter running behind
  // the mapper): the frame's points observe the vertices now in their cells. Returns fusion's stats.
  FusionStats fuseLate(const PointCloud& points_L, const Isometry3d& T_W_L, const SemanticInput& semantic);
  // Stage 2: refines the colours and classes of the vertices `input.view` sees from the LiDAR pose
  // `T_W_L` (Refinement::refine).
  RefinementStats refine(const RefinementInput& input, const Isometry3d& T_W_L);
  // Stage 2 again for a view refined earlier: colours the vertices added since (Refinement::revisit).
  RefinementStats revisit(const CameraView& view, const ViewMemory& memory);

  // Stage 2 beside the next frame (handover.cpp). A view's refinement reads the map only in its
  // look (Refinement::look); the rest reads the positions of the vertices it took and the colours,
  // and writes colours. Inserting and carving a frame add and remove points and faces, but move no
  // vertex and write no colour. So once a frame is mapped, the views due are looked at and the
  // rest of their work is handed over: the next integrate() runs it on the core that its serial
  // insert leaves idle and beside the carving, and waits for it before meshing. The results are
  // those of doing the work at once; any other call that changes the map or the mesh does it
  // first. The work gets the positions of the mesh's vertices at the hand-over.
  using HandedOver = std::function<void(Mapper&, std::span<const Eigen::Vector3f> positions)>;
  // The look of refine(input, T_W_L), taken now.
  [[nodiscard]] ViewLook lookForRefinement(const RefinementInput& input, const Isometry3d& T_W_L) const;
  // Hands `work` over to the next integrate() (after doing what was handed over before). It must
  // write nothing but colours, through refineLooked() and revisitUpTo().
  void handOver(HandedOver work);
  // Work that reads the map and the mesh's faces but no vertex position, writing none of them
  // (looks at the views due after the frame): the next integrate() runs it beside the constraint,
  // which only moves vertices, once the frame is meshed.
  void besideNextConstraint(std::function<void()> work) { beside_constraint_ = std::move(work); }
  // Does what was handed over now, if the next integrate() has not.
  void completeHandedOver();
  // For handed-over work: refine() from a look, and revisit() of the vertices at `positions`.
  RefinementStats refineLooked(const ViewLook& look, std::span<const Eigen::Vector3f> positions,
                               const RefinementInput& input, const Isometry3d& T_W_L);
  RefinementStats revisitUpTo(const CameraView& view, const ViewMemory& memory,
                              std::span<const Eigen::Vector3f> positions);
  // Gives `cls` a semantic slot (a class newly prompted); see SemanticMesh::addSemanticClass.
  void addSemanticClass(semantics::ClassId cls) { mesh_.addSemanticClass(cls); }
  // Meshes every voxel with points added since it was last meshed (and applies the semantic
  // constraint to them), then closes the mesh's small holes (params().holes). Returns how many
  // voxels it meshed.
  std::size_t finish();
  // Tiles (tile_store.hpp): where finished tiles go; until one is named, every tile stays in memory.
  void setTileDirectory(const std::filesystem::path& directory) { tiles_.setDirectory(directory); }
  [[nodiscard]] const TileStore& tiles() const { return tiles_; }
  // Writes the tiles that every position of `keep_near` (the sensor, the poses of the views stage 2
  // still holds) has left by more than params().tiles.evict_distance_m, after meshing what is
  // pending in them and closing their small holes, and drops them from memory. Vertices and voxels
  // are renumbered (see EvictionStats::new_id). Errors name the tile file. In three steps for an
  // observer that shows the closed tiles before they go: leftTiles, closeTiles, dropTiles.
  Result<EvictionStats> evictTiles(const std::vector<Eigen::Vector3f>& keep_near);
  // The tiles in memory that every position of `keep_near` has left (none without a tile folder);
  // `in_memory` gets how many tiles are in memory.
  [[nodiscard]] std::set<TileKey> leftTiles(const std::vector<Eigen::Vector3f>& keep_near,
                                            std::size_t* in_memory = nullptr) const;
  // Meshes what is pending in `tiles` and in the voxels just across their border, and closes their
  // small holes (the changes go to the mesh's change log). Returns how many voxels it meshed.
  std::size_t closeTiles(const std::set<TileKey>& tiles);
  // Writes `tiles` (closed) and drops them from memory.
  Result<EvictionStats> dropTiles(const std::set<TileKey>& tiles);
  // After finish(), when tiles were finished: writes every tile still in memory, so that the tile
  // files hold the whole map. Returns how many it wrote.
  Result<std::size_t> writeRemainingTiles();
  // The finished tiles within TileStore::reloadDistanceM() of the sensor at sensor_W.
  [[nodiscard]] std::set<TileKey> returnedTiles(const Eigen::Vector3f& sensor_W) const;
  // Loads finished tiles back from their state files (written when they left), whole: voxels,
  // vertices with their colour and class evidence, and faces, stitched to what is in memory by
  // vertex uid. They are mapped on as if they had never left (their vertices get new ids, at the
  // end). The change log of the next integrate() lists their voxels. Fails on a missing or damaged
  // state file, naming it.
  Result<ReloadStats> reloadTiles(const std::set<TileKey>& tiles);
  // What finish() closed.
  [[nodiscard]] const HoleFillStats& holeFilling() const { return hole_stats_; }

  [[nodiscard]] const SemanticMesh& mesh() const { return mesh_; }
  [[nodiscard]] const VoxelMap& voxels() const { return map_; }
  [[nodiscard]] const MapperParams& params() const { return params_; }

  // Checkpoints (mapping/checkpoint.cpp): the map, mesh and free-space state between two frames, so
  // that a mapper made with the same params and loaded goes on exactly as this one would. Not
  // after finish().
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  // Drops the faces that use points the carver removed, from the voxels that lost them and their
  // neighbours (a face's vertices lie at most one voxel from its owner), without re-meshing: what
  // those points held up goes at once, and finish() re-meshes the voxels, closing the gaps where
  // the points that stay allow it.
  void dropCarvedFaces(const CarveStats& carved);
  // What was handed over, to run beside an insert of at most `points` points (empty: nothing was).
  std::function<void()> takeHandedOver(std::size_t points);
  // Starts providing the pages of room for `vertices` more vertices and `voxels` more voxels.
  void prefaultNextFrame(std::size_t vertices, std::size_t voxels);
  // The voxels of `active` whose points grew enough since they were last meshed (or that have
  // enough for a first mesh), in the order given.
  [[nodiscard]] std::vector<VoxelKey> dueForMeshing(const std::vector<VoxelKey>& active) const;
  // The keys of `voxels` (indices) and of their 26 neighbours, sorted, once each.
  [[nodiscard]] std::vector<VoxelKey> keysAround(const std::vector<std::uint32_t>& voxels) const;
  // Meshes `keys` (1c), cutting the faces the semantic constraint refuses, then moves their
  // vertices (1d), with `beside` (when given) running meanwhile; adds the constraint's figures to
  // `stats` when given.
  std::size_t meshVoxels(const std::vector<VoxelKey>& keys, FrameStats* stats = nullptr,
                         const std::function<void()>& beside = {});
  // The voxels among `keys` with points added since they were meshed, or whose neighbours gained
  // points since then (their rim, and so the faces along their border, changed); spatially sorted.
  [[nodiscard]] std::vector<VoxelKey> pendingAmong(const std::vector<VoxelKey>& keys) const;
  // meshVoxels in chunks.
  void meshInChunks(const std::vector<VoxelKey>& keys);
  // Adds the faces that close small holes of `faces` to the voxels holding their centroids, where
  // `keep` accepts the face (all: nullptr).
  void fillHoles(const std::vector<Face>& faces, const std::function<bool(const Face&)>& keep = {});
  // Whether every corner of f lies in one of `tiles` (or, with `outside`, in none of them).
  [[nodiscard]] bool cornersIn(const Face& f, const std::set<TileKey>& tiles, bool outside = false) const;
  // Tiles: the voxels of `tiles` (sorted), and flags of them by index when `gone` is given.
  [[nodiscard]] std::vector<VoxelKey> voxelsOf(const std::set<TileKey>& tiles, std::vector<std::uint8_t>* gone) const;
  // Tiles: drops the returns that fall in finished tiles (sets drop_); returns how many.
  std::size_t dropInFinishedTiles(const std::vector<Eigen::Vector3f>& points_W);
  // Writes `tiles` (their vertices and the faces their voxels own), and with `with_state` their
  // state files, for a later visit; adds the faces written to `faces`.
  Status writeTiles(const std::set<TileKey>& tiles, std::size_t& faces, bool with_state);
  // The tile's contents: its vertices `members` (ascending uids) and the faces of `owners`.
  [[nodiscard]] TileContents tileContents(const TileKey& tile, const std::vector<std::uint32_t>& members,
                                          const std::vector<VoxelKey>& owners) const;
  // The tile's state file, its header into `head` and the rest into `body` (empty writers): its
  // vertices `members` and voxels whole, and the faces of `owners` as `contents` numbers them
  // (tile_reload.cpp).
  void tileState(const TileKey& tile, const std::vector<std::uint32_t>& members, const std::vector<VoxelKey>& owners,
                 const TileContents& contents, ArchiveWriter& head, ArchiveWriter& body) const;
  // Drops the voxels flagged `gone` and their faces, and the vertices of finished tiles that no
  // face in memory uses; fills `stats`.
  void dropFinished(const std::vector<std::uint8_t>& gone, EvictionStats& stats);

  MapperParams params_;
  VoxelMap map_;
  SemanticMesh mesh_;
  IncrementalMesher mesher_;
  SemanticFusion fusion_;
  Refinement refinement_;
  SemanticConstraint constraint_;
  SweptVolume swept_;
  FreeSpaceCarver carver_;
  HoleFillStats hole_stats_;
  TileStore tiles_;
  std::vector<Eigen::Vector3f> points_W_;
  std::vector<std::uint8_t> drop_;
  HandedOver handed_over_;                   // stage 2 work for the next integrate() (handOver)
  std::function<void()> beside_constraint_;  // work for the next integrate() (besideNextConstraint)
  std::size_t handed_vertices_ = 0;          // the mesh's vertex count at the hand-over
  std::vector<std::uint8_t> carved_flags_;   // per vertex: removed by this frame's carving (dropCarvedFaces)
  // The pages the next frame's vertices and voxels will be written to, provided by a thread of
  // their own while this frame is carved and meshed (populatePages); waited for by the next frame.
  std::future<void> prefault_;
  // The heap's pages past its last allocation (the voxels' and faces' own arrays), asked for each
  // frame and never waited for.
  HeapPrefaulter heap_prefault_{std::size_t{16} << 20};
  SemanticMesh::Changes reloaded_;  // what reloadTiles changed, for the next frame's change log
  struct Arena;
  std::unique_ptr<Arena> arena_;
};

}  // namespace artemis::mapping
