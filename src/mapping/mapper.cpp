#include "artemis/mapping/mapper.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "artemis/core/prefault.hpp"
#include "artemis/core/timer.hpp"
#include "mapper_arena.hpp"

namespace artemis::mapping {

namespace {

// Interleaves the low 21 bits of x, y and z (Morton order): voxels meshed one after the other are
// then mostly neighbours, whose points the previous voxel's rim already brought into the cache.
std::uint64_t morton(const VoxelKey& k) {
  const auto spread = [](std::uint32_t v) {
    std::uint64_t x = v & 0x1FFFFFu;
    x = (x | (x << 32)) & 0x1F00000000FFFFull;
    x = (x | (x << 16)) & 0x1F0000FF0000FFull;
    x = (x | (x << 8)) & 0x100F00F00F00F00Full;
    x = (x | (x << 4)) & 0x10C30C30C30C30C3ull;
    x = (x | (x << 2)) & 0x1249249249249249ull;
    return x;
  };
  return spread(static_cast<std::uint32_t>(k.x)) | (spread(static_cast<std::uint32_t>(k.y)) << 1) |
         (spread(static_cast<std::uint32_t>(k.z)) << 2);
}

void sortSpatially(std::vector<VoxelKey>& keys) {
  std::sort(keys.begin(), keys.end(), [](const VoxelKey& a, const VoxelKey& b) {
    const std::uint64_t ma = morton(a);
    const std::uint64_t mb = morton(b);
    return ma != mb ? ma < mb : a < b;
  });
}

}  // namespace

Mapper::Mapper(const MapperParams& params)
    : params_(params),
      map_(params.voxels),
      mesher_(params.mesher),
      fusion_(params.semantics),
      refinement_(params.refinement, params.semantics.background_score, params.semantics.geometry),
      constraint_(params.constraint, params.semantics.confidence_lambda),
      swept_(params.vehicle_box_L),
      carver_(params.free_space, params.mesher, params.vehicle_box_L),
      tiles_(params.tiles, params.voxels.voxel_size_m),
      arena_(std::make_unique<Arena>(params.threads)) {
  if (params.tiles.enabled && !(params.tiles.evict_distance_m > params.refinement.max_range_m)) {
    throw std::invalid_argument("tiles: the eviction distance (" + std::to_string(params.tiles.evict_distance_m) +
                                " m) must exceed stage 2's reach (" + std::to_string(params.refinement.max_range_m) +
                                " m): a view could still refine a finished tile");
  }
  mesh_.setVoxelPrior(static_cast<float>(params.semantics.voxel_prior));
  mesh_.setStageOneWeight(static_cast<float>(params.refinement.stage_one_weight));
}

Mapper::~Mapper() = default;

FrameStats Mapper::integrate(const PointCloud& points_L, const Isometry3d& T_W_L, const SemanticInput* semantic) {
  FrameStats stats;
  stats.points = points_L.size();
  mesh_.beginFrame();
  mesh_.addChanges(reloaded_);  // the tiles loaded back before this frame
  reloaded_ = {};
  // Fusion writes what handed-over stage 2 work may read: that work is done first.
  if (semantic != nullptr) completeHandedOver();
  Stopwatch clock;
  // The carver's look at the frame alone (its range image, its ground) needs nothing of the map: it
  // goes on another core while this thread inserts the frame, which it does mostly alone (in scan
  // order), and so does the stage 2 work handed over (handOver), after it, until the frame is
  // carved. Isolated, this thread's parallel loops until then do not take them up.
  tbb::task_group carver_look;
  tbb::task_group stage_two;
  std::function<void()> handed = takeHandedOver(points_L.size());
  arena_->arena.execute([&] {
    carver_look.run([&] { carver_.prepare(points_L.points, T_W_L); });
    if (handed) stage_two.run(handed);
  });
  const Eigen::Matrix3f R = T_W_L.linear().cast<float>();
  const Eigen::Vector3f t = T_W_L.translation().cast<float>();
  std::vector<Eigen::Vector3f>& points_W = points_W_;  // reused: no fresh pages every frame
  points_W.resize(points_L.size());
  float reach = 0.0f;     // horizontal extent of the scan around the sensor (squared, then not)
  float farthest = 0.0f;  // its farthest return (squared, then not)
  for (std::size_t i = 0; i < points_L.size(); ++i) {
    const Eigen::Vector3f& p = points_L.points[i];
    points_W[i] = R * p + t;
    const float r2 = p.head<2>().squaredNorm();
    if (r2 > reach) reach = r2;  // NaN compares false
    const float d2 = p.squaredNorm();
    if (d2 > farthest) farthest = d2;
  }
  reach = std::sqrt(reach);
  farthest = std::sqrt(farthest);
  const std::vector<std::uint8_t>* drop = nullptr;
  if (swept_.enabled() || tiles_.anyFinished()) {
    drop_.assign(points_W.size(), 0);
    drop = &drop_;
  }
  if (swept_.enabled()) {
    swept_.add(T_W_L);
    swept_.focus(t, std::min(reach, 1000.0f));
    arena_->arena.execute([&] {
      tbb::this_task_arena::isolate([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_W.size(), 4096), [&](const auto& range) {
          for (std::size_t i = range.begin(); i < range.end(); ++i) drop_[i] = swept_.contains(points_W[i]) ? 1 : 0;
        });
      });
    });
    stats.points_in_vehicle_path = static_cast<std::size_t>(std::count(drop_.begin(), drop_.end(), std::uint8_t{1}));
  }
  // Returns are looked up tile by tile only where a finished tile lies within the scan's range
  // (with tiles loaded back before the sensor comes that near, almost never).
  if (tiles_.anyFinishedWithin(t, farthest)) stats.points_in_finished_tiles = dropInFinishedTiles(points_W);
  const std::size_t vertices_before = mesh_.vertexCount();
  std::vector<VoxelKey> active;
  const bool fuse = semantic != nullptr && semantic->view != nullptr && semantic->observation != nullptr;
  if (prefault_.valid()) prefault_.get();
  const std::size_t voxels_before = map_.size();
  arena_->arena.execute([&] {
    tbb::this_task_arena::isolate([&] { active = map_.insert(points_W, t, mesh_, drop); });
    carver_look.wait();
  });
  stats.points_kept = mesh_.vertexCount() - vertices_before;
  prefaultNextFrame(2 * stats.points_kept, 2 * (map_.size() - voxels_before));
  stats.active_voxels = active.size();
  stats.insert_ms = clock.elapsedMs();
  clock.reset();
  CarveStats carved;
  arena_->arena.execute([&] { carved = carver_.carve(points_L.points, T_W_L, map_, active); });
  dropCarvedFaces(carved);
  stats.carve_ms = clock.elapsedMs();
  // Inserting and carving add and remove points and faces but move no vertex and write no colour:
  // the handed-over work saw the state it was handed over in. (Running it beside meshing too was
  // no faster: it then slowed the meshing down as much.)
  clock.reset();
  arena_->arena.execute([&] { stage_two.wait(); });
  stats.stage_two_wait_ms = clock.elapsedMs();
  stats.points_carved = carved.vertices.size();
  stats.points_tested_free = carved.points_tested;

  if (fuse) {
    FusionStats f;
    arena_->arena.execute([&] {
      f = fusion_.fuse(points_L, map_, T_W_L, *semantic->view, *semantic->observation, mesh_, semantic->vocabulary);
    });
    stats.fuse_ms = f.ms;
    stats.semantic_observations = f.observations;
  }

  clock.reset();
  std::vector<VoxelKey> due = dueForMeshing(active);
  sortSpatially(due);
  const std::function<void()> beside = std::move(beside_constraint_);
  beside_constraint_ = nullptr;
  stats.meshed_voxels = meshVoxels(due, &stats, beside);
  stats.mesh_ms = clock.elapsedMs() - stats.constrain_ms - stats.beside_constraint_wait_ms;
  return stats;
}

std::vector<VoxelKey> Mapper::dueForMeshing(const std::vector<VoxelKey>& active) const {
  // Looked up side by side (a hash probe each, ~10,000 a KITTI frame), kept in the order given.
  std::vector<std::uint8_t> is_due(active.size(), 0);
  arena_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, active.size(), 512), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        const Voxel& v = *map_.find(active[i]);
        const auto now = static_cast<double>(v.vertices.size());
        const auto before = static_cast<double>(v.points_when_meshed);
        const double grown = now - before;
        const bool first = before == 0.0 && now >= params_.first_mesh_points;
        is_due[i] = first || (before > 0.0 && grown >= std::max(static_cast<double>(params_.remesh_min_new),
                                                                params_.remesh_growth * before));
      }
    });
  });
  std::vector<VoxelKey> due;
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (is_due[i] != 0) due.push_back(active[i]);
  }
  return due;
}

void Mapper::prefaultNextFrame(std::size_t vertices, std::size_t voxels) {
  std::vector<ByteRange> room = mesh_.roomAhead(vertices);
  const std::vector<ByteRange> voxel_room = map_.roomAhead(voxels);
  room.insert(room.end(), voxel_room.begin(), voxel_room.end());
  // populatePages is safe while the arrays are written, and even once one moves (a range no longer
  // mapped is left alone).
  prefault_ = std::async(std::launch::async, [room = std::move(room)] {
    for (const ByteRange& r : room) populatePages(r);
  });
  heap_prefault_.request();
}

FusionStats Mapper::fuseLate(const PointCloud& points_L, const Isometry3d& T_W_L, const SemanticInput& semantic) {
  if (semantic.view == nullptr || semantic.observation == nullptr) return {};
  completeHandedOver();
  FusionStats f;
  arena_->arena.execute([&] {
    f = fusion_.fuseLate(points_L, map_, T_W_L, *semantic.view, *semantic.observation, mesh_, semantic.vocabulary);
  });
  return f;
}

RefinementStats Mapper::refine(const RefinementInput& input, const Isometry3d& T_W_L) {
  completeHandedOver();
  RefinementStats stats;
  arena_->arena.execute([&] { stats = refinement_.refine(map_, mesh_, input, T_W_L); });
  return stats;
}

RefinementStats Mapper::revisit(const CameraView& view, const ViewMemory& memory) {
  completeHandedOver();
  RefinementStats stats;
  arena_->arena.execute([&] { stats = refinement_.revisit(mesh_, view, memory); });
  return stats;
}

std::size_t Mapper::finish() {
  completeHandedOver();
  mesh_.beginFrame();
  const std::vector<VoxelKey> pending = pendingAmong(map_.keys());
  meshInChunks(pending);
  if (tiles_.anyFinished()) {
    // Holes along the border of a finished tile stay open: their other side left memory, and the
    // tile's own fills may already close some of them (tile_eviction.cpp).
    fillHoles(mesh_.faces(), [&](const Face& f) { return cornersIn(f, tiles_.finishedTiles(), true); });
  } else {
    fillHoles(mesh_.faces());
  }
  return pending.size();
}

std::vector<VoxelKey> Mapper::pendingAmong(const std::vector<VoxelKey>& keys) const {
  std::vector<VoxelKey> pending;
  for (const VoxelKey& key : keys) {
    const Voxel& v = *map_.find(key);
    bool stale = v.vertices.size() > v.points_when_meshed || v.carved_frame > v.meshed_frame;
    for (int dx = -1; dx <= 1 && !stale; ++dx) {
      for (int dy = -1; dy <= 1 && !stale; ++dy) {
        for (int dz = -1; dz <= 1 && !stale; ++dz) {
          const Voxel* n = map_.find({key.x + dx, key.y + dy, key.z + dz});
          stale = n != nullptr && n->active_frame > v.meshed_frame && v.points_when_meshed > 0;
        }
      }
    }
    if (stale) pending.push_back(key);
  }
  sortSpatially(pending);
  return pending;
}

void Mapper::meshInChunks(const std::vector<VoxelKey>& keys) {
  // In spatially sorted chunks the size of a busy frame's work, so that the constraint's patch (a
  // few hundred bytes a vertex) stays small however much of the map is pending.
  constexpr std::size_t kChunk = 4096;
  for (std::size_t begin = 0; begin < keys.size(); begin += kChunk) {
    const auto first = keys.begin() + static_cast<std::ptrdiff_t>(begin);
    meshVoxels({first, first + static_cast<std::ptrdiff_t>(std::min(kChunk, keys.size() - begin))});
  }
}

void Mapper::fillHoles(const std::vector<Face>& faces, const std::function<bool(const Face&)>& keep) {
  HoleFillStats stats;
  const std::vector<Face> fills =
      holeFillingFaces(faces, mesh_.positions(), params_.mesher.max_edge_m, params_.holes, &stats);
  hole_stats_ += stats;
  // Owned like the mesher's faces: by the voxel holding the centroid, else by the voxel of origin
  // of the smallest vertex id.
  std::map<VoxelKey, std::vector<Face>> by_owner;
  const float inv_size = 1.0f / map_.voxelSize();
  const auto& p = mesh_.positions();
  for (const Face& f : fills) {
    VoxelKey owner = voxelKeyOf((p[f[0]] + p[f[1]] + p[f[2]]) / 3.0f, inv_size);
    if (map_.find(owner) == nullptr) owner = mesh_.voxels()[std::min({f[0], f[1], f[2]})];
    if (!keep || keep(f)) by_owner[owner].push_back(f);
  }
  for (auto& [owner, added] : by_owner) {
    const std::vector<Face>* own = mesh_.voxelFaces(owner);
    std::vector<Face> merged = own != nullptr ? *own : std::vector<Face>{};
    merged.insert(merged.end(), added.begin(), added.end());
    mesh_.setVoxelFaces(owner, std::move(merged));
  }
}

std::size_t Mapper::meshVoxels(const std::vector<VoxelKey>& keys, FrameStats* stats,
                               const std::function<void()>& beside) {
  std::vector<VoxelMeshResult> results(keys.size());
  std::vector<std::size_t> cut(keys.size(), 0);
  const bool constrain = params_.constraint.enabled && mesh_.slotCount() > 1;
  arena_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        results[i] = mesher_.meshVoxel(map_, mesh_, keys[i]);
        if (!constrain) continue;
        auto& faces = results[i].faces;
        const std::size_t before = faces.size();
        std::erase_if(faces, [&](const Face& f) { return constraint_.cuts(mesh_, f); });
        cut[i] = before - faces.size();
      }
    });
  });
  // Apply in key order of the input: deterministic whatever the thread count.
  for (VoxelMeshResult& r : results) {
    Voxel& v = *map_.find(r.key);
    v.points_when_meshed = static_cast<std::uint32_t>(v.vertices.size());
    v.meshed_frame = map_.frame();
    v.plane_normal = r.planar ? r.normal : Eigen::Vector3f::Zero();
    v.plane_points = v.points_when_meshed;
    if (r.normal != Eigen::Vector3f::Zero()) {
      for (std::uint32_t id : v.vertices) mesh_.setNormal(id, r.normal);
    }
    const std::vector<Face>* old = mesh_.voxelFaces(r.key);
    if (old == nullptr && r.faces.empty()) continue;
    mesh_.setVoxelFaces(r.key, std::move(r.faces));
  }
  Stopwatch clock;
  ConstraintStats constrained;
  tbb::task_group beside_group;  // on the core the constraint's serial parts leave idle
  arena_->arena.execute([&] {
    if (beside) beside_group.run(beside);
    if (params_.constraint.enabled) constrained = constraint_.apply(map_, mesh_, keys);
  });
  const double constrain_ms = clock.elapsedMs();
  arena_->arena.execute([&] { beside_group.wait(); });
  if (stats != nullptr) {
    stats->constrain_ms = constrain_ms;
    stats->beside_constraint_wait_ms = clock.elapsedMs() - constrain_ms;
    for (const std::size_t c : cut) stats->faces_cut += c;
    stats->constraint = constrained;
  }
  return keys.size();
}

}  // namespace artemis::mapping
