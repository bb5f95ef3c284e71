#include "artemis/mapping/semantic_constraint.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "artemis/core/timer.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis::mapping {

using Eigen::Vector3d;

SemanticConstraint::SemanticConstraint(const SemanticConstraintParams& params, double confidence_lambda)
    : params_(params), confidence_lambda_(confidence_lambda) {
  const auto ok = [](double value) { return std::isfinite(value) && value >= 0.0; };
  if (!ok(params.lambda_sem) || !ok(params.lambda_smooth) || !ok(params.temperature) || !ok(params.tolerance) ||
      !ok(params.max_offset_m) || !ok(params.min_step_m) || !(params.max_step_m > 0.0) || !ok(params.max_step_m) ||
      !ok(params.cut_similarity) || !ok(params.cut_depth_gap_m) || params.max_sweeps < 1 || params.steps < 1 ||
      !(confidence_lambda > 0.0)) {
    throw std::invalid_argument(
        "semantic constraint: lambda_sem, lambda_smooth, temperature, tolerance, max_offset_m, cut_similarity and "
        "cut_depth_gap_m must be finite and >= 0, max_step_m and the confidence lambda > 0, sweeps and steps >= 1");
  }
}

bool SemanticConstraint::cuts(const SemanticMesh& mesh, const Face& f) const {
  const auto& x = mesh.positions();
  const auto& views = mesh.viewDirections();
  thread_local std::vector<float> p;
  thread_local std::vector<float> q;
  const std::size_t slots = mesh.slotCount();
  if (slots < 2) return false;
  p.resize(slots);
  q.resize(slots);
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t a = f[static_cast<std::size_t>(k)];
    const std::uint32_t b = f[static_cast<std::size_t>((k + 1) % 3)];
    const Eigen::Vector3f ray = (views[a] + views[b]).normalized();
    if (!(std::abs((x[a] - x[b]).dot(ray)) > params_.cut_depth_gap_m)) continue;
    if (!mesh.distribution(a, p.data()) || !mesh.distribution(b, q.data())) continue;  // unobserved: no evidence
    const double similarity = semanticSimilarity(jensenShannon(p.data(), q.data(), slots), params_.temperature);
    if (similarity < params_.cut_similarity) return true;
  }
  return false;
}

ConstraintStats SemanticConstraint::apply(const VoxelMap& map, SemanticMesh& mesh,
                                          const std::vector<VoxelKey>& meshed) {
  ConstraintStats stats;
  if (!params_.enabled || meshed.empty()) return stats;
  Stopwatch clock;

  // The patch: faces of the meshed voxels and of their neighbours.
  std::vector<VoxelKey> keys;
  keys.reserve(meshed.size() * 27);
  for (const VoxelKey& key : meshed) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) keys.push_back({key.x + dx, key.y + dy, key.z + dz});
      }
    }
  }
  tbb::parallel_sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());

  if (local_of_.size() < mesh.vertexCount()) {
    level_.resize(mesh.vertexCount(), 0);
    stamp_.resize(mesh.vertexCount(), 0);
    local_of_.resize(mesh.vertexCount(), 0);
    numbered_.resize(mesh.vertexCount(), 0);
  }
  if (++current_stamp_ == 0) {  // wrapped: forget every old stamp
    std::fill(stamp_.begin(), stamp_.end(), 0);
    std::fill(numbered_.begin(), numbered_.end(), 0);
    current_stamp_ = 1;
  }
  // Level of each vertex this solve: 1 active (may move), 2 a neighbour of one (its normal moves).
  const auto level = [&](std::uint32_t v) { return stamp_[v] == current_stamp_ ? level_[v] : std::uint8_t{0}; };
  const auto mark = [&](std::uint32_t v, std::uint8_t l) {
    stamp_[v] = current_stamp_;
    level_[v] = l;
  };
  for (const VoxelKey& key : meshed) {
    const Voxel* voxel = map.find(key);
    if (voxel == nullptr) continue;
    for (const std::uint32_t v : voxel->vertices) mark(v, 1);
  }
  // The face lists around the meshed voxels (looked up in parallel, kept in key order).
  std::vector<const std::vector<Face>*> lists(keys.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), 256), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) lists[k] = mesh.voxelFaces(keys[k]);
  });
  std::erase(lists, nullptr);
  // Faces of the lists that pass `keep`, in list order: counted, then gathered, in parallel.
  const auto select = [&](const auto& keep) {
    std::vector<std::size_t> offset(lists.size() + 1, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.size(), 64), [&](const auto& range) {
      for (std::size_t k = range.begin(); k < range.end(); ++k) {
        offset[k + 1] = static_cast<std::size_t>(std::count_if(lists[k]->begin(), lists[k]->end(), keep));
      }
    });
    for (std::size_t k = 0; k < lists.size(); ++k) offset[k + 1] += offset[k];
    std::vector<Face> selected(offset.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lists.size(), 64), [&](const auto& range) {
      for (std::size_t k = range.begin(); k < range.end(); ++k) {
        std::copy_if(lists[k]->begin(), lists[k]->end(), selected.begin() + static_cast<std::ptrdiff_t>(offset[k]),
                     keep);
      }
    });
    return selected;
  };
  for (const Face& f :
       select([&](const Face& f) { return level(f[0]) == 1 || level(f[1]) == 1 || level(f[2]) == 1; })) {
    for (const std::uint32_t v : f) {
      if (level(v) == 0) mark(v, 2);
    }
  }
  // The patch: every face with an active vertex or a neighbour of one (what their normals sum).
  ConstraintPatch patch;
  patch.slots = mesh.slotCount();
  patch.faces = select([&](const Face& f) { return level(f[0]) != 0 || level(f[1]) != 0 || level(f[2]) != 0; });
  std::vector<std::uint32_t> global;  // patch index -> mesh vertex
  for (Face& f : patch.faces) {
    for (std::uint32_t& v : f) {
      if (numbered_[v] != current_stamp_) {
        numbered_[v] = current_stamp_;
        local_of_[v] = static_cast<std::uint32_t>(global.size());
        global.push_back(v);
      }
      v = local_of_[v];
    }
  }
  const std::size_t n = global.size();
  patch.positions.resize(n);
  patch.measured.resize(n);
  patch.plane_normals.resize(n);
  patch.confidence.resize(n);
  patch.distributions.resize(n * patch.slots);
  patch.active.assign(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const std::uint32_t v = global[i];
      patch.positions[i] = mesh.positions()[v];
      patch.measured[i] = mesh.measuredPositions()[v];
      patch.plane_normals[i] = mesh.normals()[v];
      patch.confidence[i] = mesh.confidence(v, confidence_lambda_);
      patch.active[i] = level(v) == 1 ? 1 : 0;
      float* out = &patch.distributions[i * patch.slots];
      if (!mesh.distribution(v, out)) std::fill_n(out, patch.slots, 1.0f / static_cast<float>(patch.slots));
    }
  });
  // Parallel schedule: blocks of b^3 voxels coloured by the parity of their coordinates. Two
  // vertices of same-coloured blocks are at least b voxels apart, less what each may move; a
  // vertex's update reads and writes within three edges of it, and no edge of the patch can grow
  // beyond its measured length plus twice max_offset_m.
  double longest = 0.0;
  for (const Face& f : patch.faces) {
    for (int k = 0; k < 3; ++k) {
      const double length =
          (patch.measured[f[static_cast<std::size_t>(k)]] - patch.measured[f[static_cast<std::size_t>((k + 1) % 3)]])
              .norm();
      longest = std::max(longest, length);
    }
  }
  const double reach = 3.0 * (longest + 2.0 * params_.max_offset_m) + 2.0 * params_.max_offset_m;
  const auto side = static_cast<std::int32_t>(std::floor(reach / map.voxelSize())) + 1;
  patch.block.resize(n);
  patch.colour.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const VoxelKey block = coarserKey(mesh.voxels()[global[i]], side);
      patch.block[i] = block;
      patch.colour[i] = static_cast<std::uint8_t>((block.x & 1) | ((block.y & 1) << 1) | ((block.z & 1) << 2));
    }
  });
  stats.patch_vertices = n;
  stats.active_vertices = static_cast<std::size_t>(std::count(patch.active.begin(), patch.active.end(), 1));
  stats.patch_ms = clock.elapsedMs();

  ConstraintSolver solver(params_, patch);
  stats.build_ms = clock.elapsedMs() - stats.patch_ms;
  solver.solve(stats);
  stats.solve_ms = clock.elapsedMs() - stats.patch_ms - stats.build_ms;
  for (std::size_t i = 0; i < n; ++i) {
    if (patch.active[i] != 0) mesh.setPosition(global[i], patch.positions[i]);
  }
  stats.ms = clock.elapsedMs();
  return stats;
}

}  // namespace artemis::mapping
