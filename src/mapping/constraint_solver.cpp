// The semantic constraint's solver (semantic_constraint.hpp: the energy of eq. 2-8 and how it is
// lowered), apart from the stage that builds its patch and applies its result.
#include "artemis/mapping/semantic_constraint.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace artemis::mapping {

using Eigen::Vector3d;

double jensenShannon(const float* p, const float* q, std::size_t n) {
  // JS = 1/2 KL(P || M) + 1/2 KL(Q || M), M = (P + Q) / 2; 0 log 0 = 0.
  double js = 0.0;
  for (std::size_t s = 0; s < n; ++s) {
    const double a = p[s];
    const double b = q[s];
    const double m = 0.5 * (a + b);
    if (a > 0.0) js += 0.5 * a * std::log(a / m);
    if (b > 0.0) js += 0.5 * b * std::log(b / m);
  }
  return std::clamp(js, 0.0, std::log(2.0));
}

ConstraintSolver::ConstraintSolver(const SemanticConstraintParams& params, ConstraintPatch& patch)
    : params_(params), patch_(patch) {
  const std::size_t n = patch.positions.size();
  if (patch.measured.size() != n || patch.plane_normals.size() != n || patch.confidence.size() != n ||
      patch.active.size() != n || patch.slots == 0 || patch.distributions.size() != n * patch.slots) {
    throw std::invalid_argument("ConstraintSolver: the patch's per-vertex arrays must all have " + std::to_string(n) +
                                " entries (distributions: " + std::to_string(patch.slots) + " per vertex)");
  }
  indexFaces();
  gatherNeighbours();
  startGeometry();
  orderPhases();
}

// vertex -> faces (CSR); a face naming a vertex out of range is refused.
void ConstraintSolver::indexFaces() {
  const ConstraintPatch& patch = patch_;
  const std::size_t n = patch.positions.size();
  face_offsets_.assign(n + 1, 0);
  for (const Face& f : patch.faces) {
    for (const std::uint32_t v : f) {
      if (v >= n) {
        throw std::invalid_argument("ConstraintSolver: a face names vertex " + std::to_string(v) + " of " +
                                    std::to_string(n));
      }
      ++face_offsets_[v + 1];
    }
  }
  for (std::size_t v = 0; v < n; ++v) face_offsets_[v + 1] += face_offsets_[v];
  vertex_faces_.resize(face_offsets_[n]);
  {
    std::vector<std::uint32_t> fill(face_offsets_.begin(), face_offsets_.end() - 1);
    for (std::size_t f = 0; f < patch.faces.size(); ++f) {
      for (const std::uint32_t v : patch.faces[f]) vertex_faces_[fill[v]++] = static_cast<std::uint32_t>(f);
    }
  }
}

void ConstraintSolver::gatherNeighbours() {
  const ConstraintPatch& patch = patch_;
  const SemanticConstraintParams& params = params_;
  const std::size_t n = patch.positions.size();
  // Neighbours: the other corners of a vertex's faces, sorted and unique, each with its edge's
  // constants (the distributions do not change during a solve). Only the vertices whose energy
  // terms can change need them: the active ones and their neighbours (whose normals move). Each is
  // gathered once, in parallel, into room for twice its faces (the most it can have), then packed.
  std::vector<std::uint8_t> needs(n, 0);
  for (const Face& f : patch.faces) {
    if (patch.active[f[0]] != 0 || patch.active[f[1]] != 0 || patch.active[f[2]] != 0) {
      for (const std::uint32_t v : f) needs[v] = 1;
    }
  }
  std::vector<std::uint32_t> room(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) {
    room[v + 1] = room[v] + (needs[v] != 0 ? 2 * (face_offsets_[v + 1] - face_offsets_[v]) : 0);
  }
  std::vector<Neighbour> gathered(room[n]);
  neighbour_offsets_.assign(n + 1, 0);
  const std::size_t slots = patch.slots;
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(n), 256), [&](const auto& range) {
    // Each neighbour once (a fan names most of them twice): marked with a number no earlier
    // vertex, or patch, used on this thread; then only the distinct ones are sorted.
    thread_local std::vector<std::uint32_t> around;
    thread_local std::vector<std::uint64_t> seen;
    thread_local std::uint64_t mark = 0;
    if (seen.size() < n) seen.resize(n, 0);
    for (std::uint32_t v = range.begin(); v < range.end(); ++v) {
      if (needs[v] == 0) continue;
      around.clear();
      ++mark;
      for (std::uint32_t k = face_offsets_[v]; k < face_offsets_[v + 1]; ++k) {
        for (const std::uint32_t u : patch.faces[vertex_faces_[k]]) {
          if (u != v && seen[u] != mark) {
            seen[u] = mark;
            around.push_back(u);
          }
        }
      }
      std::sort(around.begin(), around.end());
      neighbour_offsets_[v + 1] = static_cast<std::uint32_t>(around.size());
      const float* p = &patch.distributions[v * slots];
      for (std::size_t i = 0; i < around.size(); ++i) {
        const std::uint32_t u = around[i];
        const float* q = &patch.distributions[u * slots];
        // Equal distributions (both never observed, or one voxel's prior) are common: JS 0, sim 1.
        if (std::equal(p, p + slots, q)) {
          gathered[room[v] + i] = {u, 1.0f, 0.0f};
          continue;
        }
        const double js = jensenShannon(p, q, slots);
        gathered[room[v] + i] = {
            u, static_cast<float>(semanticSimilarity(js, params.temperature)),
            static_cast<float>(static_cast<double>(patch.confidence[v]) * patch.confidence[u] * js)};
      }
    }
  });
  for (std::size_t v = 0; v < n; ++v) neighbour_offsets_[v + 1] += neighbour_offsets_[v];
  neighbours_.resize(neighbour_offsets_[n]);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(n), 1024), [&](const auto& range) {
    for (std::uint32_t v = range.begin(); v < range.end(); ++v) {
      std::copy_n(gathered.begin() + room[v], neighbour_offsets_[v + 1] - neighbour_offsets_[v],
                  neighbours_.begin() + neighbour_offsets_[v]);
    }
  });
}

// Positions in double, every vertex's normal, and each neighbour entry's edge length.
void ConstraintSolver::startGeometry() {
  const std::size_t n = patch_.positions.size();
  x_.resize(n);
  for (std::size_t v = 0; v < n; ++v) x_[v] = patch_.positions[v].cast<double>();
  area_normals_.resize(n);
  normals_.resize(n);
  lengths_.resize(neighbours_.size());
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(n), 1024), [&](const auto& range) {
    for (std::uint32_t v = range.begin(); v < range.end(); ++v) {
      refreshNormal(v);
      for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) {
        lengths_[k] = (x_[v] - x_[neighbours_[k].vertex]).norm();
      }
    }
  });
}

// The sweep's schedule: the active vertices, in one group, or by colour and block (see
// ConstraintPatch::block).
void ConstraintSolver::orderPhases() {
  const ConstraintPatch& patch = patch_;
  const std::size_t n = patch.positions.size();
  if (patch.block.empty()) {
    phases_.resize(1);
    phases_[0].resize(1);
    for (std::uint32_t v = 0; v < n; ++v) {
      if (patch.active[v] != 0) phases_[0][0].push_back(v);
    }
  } else {
    if (patch.block.size() != n || patch.colour.size() != n) {
      throw std::invalid_argument("ConstraintSolver: block and colour need one entry per vertex");
    }
    struct Slot {
      std::uint8_t colour;
      VoxelKey block;
      std::uint32_t vertex;
    };
    std::vector<Slot> order;
    for (std::uint32_t v = 0; v < n; ++v) {
      if (patch.active[v] != 0) order.push_back({patch.colour[v], patch.block[v], v});
    }
    tbb::parallel_sort(order.begin(), order.end(), [](const Slot& a, const Slot& b) {
      return a.colour != b.colour ? a.colour < b.colour : a.block != b.block ? a.block < b.block : a.vertex < b.vertex;
    });
    for (std::size_t i = 0; i < order.size(); ++i) {
      const bool new_colour = i == 0 || order[i].colour != order[i - 1].colour;
      if (new_colour) phases_.emplace_back();
      if (new_colour || order[i].block != order[i - 1].block) phases_.back().emplace_back();
      phases_.back().back().push_back(order[i].vertex);
    }
  }
}

ConstraintEnergy ConstraintSolver::energy() const {
  // Per fixed range of vertices in parallel, then the ranges in order: the same sum on any thread
  // count.
  constexpr std::size_t kRange = 2048;
  const std::size_t n = patch_.positions.size();
  std::vector<ConstraintEnergy> parts((n + kRange - 1) / kRange);
  tbb::parallel_for(std::size_t{0}, parts.size(), [&](std::size_t r) {
    ConstraintEnergy& e = parts[r];
    for (std::size_t v = r * kRange; v < std::min(n, (r + 1) * kRange); ++v) {
      const double d = patch_.plane_normals[v].cast<double>().dot(x_[v] - patch_.measured[v].cast<double>());
      e.geometry += d * d;
      for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) {
        const Neighbour& nb = neighbours_[k];
        // Each edge once: from its lower end, or from the end with neighbours when only one has them.
        if (nb.vertex < v && neighbour_offsets_[nb.vertex + 1] > neighbour_offsets_[nb.vertex]) continue;
        const double length = (x_[v] - x_[nb.vertex]).norm();
        if (!(length > 0.0)) continue;
        e.semantic += nb.semantic / length;
        e.smoothness += nb.similarity / length * (normals_[v] - normals_[nb.vertex]).squaredNorm();
      }
    }
  });
  ConstraintEnergy e;
  for (const ConstraintEnergy& part : parts) {
    e.geometry += part.geometry;
    e.semantic += part.semantic;
    e.smoothness += part.smoothness;
  }
  e.total = e.geometry + params_.lambda_sem * e.semantic + params_.lambda_smooth * e.smoothness;
  return e;
}

double ConstraintSolver::sweep() {
  double lowered = 0.0;
  std::vector<double> per_group;
  for (const auto& groups : phases_) {
    per_group.assign(groups.size(), 0.0);
    tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
      for (const std::uint32_t v : groups[g]) per_group[g] += relax(v);
    });
    for (const double d : per_group) lowered += d;  // in group order: the same sum on any thread count
  }
  return lowered;
}

void ConstraintSolver::solve(ConstraintStats& stats) {
  double e = energy().total;
  stats.energy_before = e;
  stats.sweeps = 0;
  for (int s = 0; s < params_.max_sweeps; ++s) {
    const double lowered = sweep();
    ++stats.sweeps;
    e -= lowered;
    if (!(lowered > params_.tolerance * std::abs(e))) break;
  }
  stats.energy_after = e;
}

}  // namespace artemis::mapping
