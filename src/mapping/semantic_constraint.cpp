#include "artemis/mapping/semantic_constraint.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "artemis/core/timer.hpp"
#include "artemis/mapping/voxel_map.hpp"

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

  x_.resize(n);
  for (std::size_t v = 0; v < n; ++v) x_[v] = patch.positions[v].cast<double>();
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

Vector3d ConstraintSolver::areaNormal(std::uint32_t v, std::uint32_t moved, const Vector3d& x) const {
  Vector3d m = Vector3d::Zero();
  for (std::uint32_t k = face_offsets_[v]; k < face_offsets_[v + 1]; ++k) {
    const Face& f = patch_.faces[vertex_faces_[k]];
    const Vector3d a = position(f[0], moved, x);
    m += (position(f[1], moved, x) - a).cross(position(f[2], moved, x) - a);
  }
  return m;
}

void ConstraintSolver::refreshNormal(std::uint32_t v) {
  area_normals_[v] = areaNormal(v, std::numeric_limits<std::uint32_t>::max(), Vector3d::Zero());
  const double length = area_normals_[v].norm();
  normals_[v] = length > 0.0 ? Vector3d(area_normals_[v] / length) : Vector3d::Zero();
}

namespace {

// The vertices whose normals move with vertex v: v and its neighbours, with their normals at the
// trial position, and the index of each among them (per-thread scratch; `slot` is stamped, so it
// is never cleared).
struct MovedNormals {
  std::vector<std::uint32_t> vertex;
  std::vector<Vector3d> area;    // m
  std::vector<Vector3d> normal;  // n
  std::vector<Vector3d> adjoint;
  // Per patch vertex, side by side so that a lookup touches one cache line: its index into
  // `vertex`, valid when its stamp equals `current`.
  struct Entry {
    std::uint32_t stamp = 0;
    std::uint32_t slot = 0;
  };
  std::vector<Entry> entries;
  std::uint32_t current = 0;

  void begin(std::size_t patch_size) {
    if (entries.size() < patch_size) entries.resize(patch_size);
    if (++current == 0) {  // wrapped: forget every old stamp
      std::fill(entries.begin(), entries.end(), Entry{});
      current = 1;
    }
    vertex.clear();
    area.clear();
    normal.clear();
  }
  void add(std::uint32_t v) {
    entries[v] = {current, static_cast<std::uint32_t>(vertex.size())};
    vertex.push_back(v);
  }
  [[nodiscard]] int find(std::uint32_t v) const {
    const Entry& e = entries[v];
    return e.stamp == current ? static_cast<int>(e.slot) : -1;
  }
};

// The scratch of the calling thread (evaluate fills it; relax reads the accepted position's normals).
MovedNormals& movedScratch() {
  thread_local MovedNormals moved;
  return moved;
}

Vector3d unit(const Vector3d& m) {
  const double length = m.norm();
  return length > 0.0 ? Vector3d(m / length) : Vector3d::Zero();
}

}  // namespace

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

void ConstraintSolver::checkMovable(std::uint32_t v) const {
  // A vertex with faces but no neighbour list is neither active nor next to an active vertex: the
  // solver kept nothing to evaluate its terms with.
  if (v >= x_.size() ||
      (neighbour_offsets_[v + 1] == neighbour_offsets_[v] && face_offsets_[v + 1] > face_offsets_[v])) {
    throw std::invalid_argument("ConstraintSolver: vertex " + std::to_string(v) +
                                " is out of range, or neither active nor next to an active vertex");
  }
}

ConstraintEnergy ConstraintSolver::localEnergy(std::uint32_t v, const Vector3d& x) const {
  checkMovable(v);
  ConstraintEnergy e;
  evaluate(v, x, &e, nullptr);
  return e;
}

std::array<Vector3d, 3> ConstraintSolver::localGradient(std::uint32_t v, const Vector3d& x) const {
  checkMovable(v);
  std::array<Vector3d, 3> g;
  evaluate(v, x, nullptr, &g);
  return g;
}

void ConstraintSolver::evaluate(std::uint32_t v, const Vector3d& x, ConstraintEnergy* energy,
                                std::array<Vector3d, 3>* gradient) const {
  // Stamps only grow (all are cleared when they wrap), so an entry left by an earlier call, or an
  // earlier patch, never matches.
  MovedNormals& moved = movedScratch();
  moved.begin(x_.size());
  const auto add = [&](std::uint32_t u) {
    moved.add(u);
    moved.area.push_back(area_normals_[u]);
  };
  add(v);
  for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) add(neighbours_[k].vertex);
  // Only the faces of v change with x: each adds its change of area vector to its three corners
  // (all of them v or its neighbours), so the moved normals cost one pass over v's faces.
  for (std::uint32_t k = face_offsets_[v]; k < face_offsets_[v + 1]; ++k) {
    const Face& f = patch_.faces[vertex_faces_[k]];
    const Vector3d& a = x_[f[0]];
    const Vector3d& b = x_[f[1]];
    const Vector3d& c = x_[f[2]];
    const Vector3d& a2 = position(f[0], v, x);
    const Vector3d& b2 = position(f[1], v, x);
    const Vector3d& c2 = position(f[2], v, x);
    const Vector3d change = (b2 - a2).cross(c2 - a2) - (b - a).cross(c - a);
    for (const std::uint32_t corner : f) moved.area[static_cast<std::size_t>(moved.find(corner))] += change;
  }
  for (const Vector3d& m : moved.area) moved.normal.push_back(unit(m));
  const auto normal_of = [&](std::uint32_t q) -> const Vector3d& {
    const int j = moved.find(q);
    return j >= 0 ? moved.normal[static_cast<std::size_t>(j)] : normals_[q];
  };
  const Vector3d n_plane = patch_.plane_normals[v].cast<double>();
  const double d = n_plane.dot(x - patch_.measured[v].cast<double>());

  // One pass over every edge with an end whose normal moves gives both E_smoothness (an edge with
  // both ends moving counts once) and, for the gradient, each moved normal's dE/dn_p =
  // sum_q 2 w_pq (n_p - n_q) (every edge of p).
  const bool want_gradient = gradient != nullptr;
  double smoothness = 0.0;
  if (want_gradient) moved.adjoint.assign(moved.vertex.size(), Vector3d::Zero());
  for (std::size_t i = 0; i < moved.vertex.size(); ++i) {
    const std::uint32_t p = moved.vertex[i];
    Vector3d a = Vector3d::Zero();
    for (std::uint32_t k = neighbour_offsets_[p]; k < neighbour_offsets_[p + 1]; ++k) {
      const std::uint32_t q = neighbours_[k].vertex;
      const bool counted = energy != nullptr && !(q < p && moved.find(q) >= 0);
      if (!counted && !want_gradient) continue;
      const double length = edgeLength(p, q, k, v, x);
      if (!(length > 0.0)) continue;
      const double w = neighbours_[k].similarity / length;
      const Vector3d diff = moved.normal[i] - normal_of(q);
      if (counted) smoothness += w * diff.squaredNorm();
      if (want_gradient) a += 2.0 * w * diff;
    }
    if (want_gradient) moved.adjoint[i] = a;  // turned into dE/dm_p below
  }

  if (energy != nullptr) {
    ConstraintEnergy& e = *energy;
    e = {};
    e.geometry = d * d;
    for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) {
      const double length = (x - x_[neighbours_[k].vertex]).norm();
      if (length > 0.0) e.semantic += neighbours_[k].semantic / length;
    }
    e.smoothness = smoothness;
    e.total = e.geometry + params_.lambda_sem * e.semantic + params_.lambda_smooth * e.smoothness;
  }
  if (!want_gradient) return;

  std::array<Vector3d, 3>& g = *gradient;
  // Geometry: d/dx (n . (x - p))^2.
  g[0] = 2.0 * d * n_plane;
  g[1] = Vector3d::Zero();
  g[2] = Vector3d::Zero();
  // Semantic and the edge-length part of smoothness: d/dx (1 / |x - x_j|) = -(x - x_j) / L^3.
  for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) {
    const Neighbour& nb = neighbours_[k];
    const Vector3d e = x - x_[nb.vertex];
    const double length = e.norm();
    if (!(length > 0.0)) continue;
    const Vector3d d_inv_length = -e / (length * length * length);
    g[1] += nb.semantic * d_inv_length;
    const auto j = static_cast<std::size_t>(k - neighbour_offsets_[v]) + 1;  // moved index of nb.vertex
    g[2] += nb.similarity * (moved.normal[0] - moved.normal[j]).squaredNorm() * d_inv_length;
  }
  // The normal part of smoothness. Through n = m / |m|, dE/dm_p = (I - n n^T) dE/dn_p / |m_p|
  // = u_p. m_p sums its faces' area vectors m_f = x0 x x1 + x1 x x2 + x2 x x0, whose derivative
  // with respect to corner k is [x_{k-1} - x_{k+1}]_x, so u . dm_f/dx_k = u x (x_{k-1} - x_{k+1})
  // as a gradient. Summed over the faces of v: sum_f (sum of u over f's corners) x (...).
  for (std::size_t i = 0; i < moved.vertex.size(); ++i) {
    const double m_length = moved.area[i].norm();
    if (!(m_length > 0.0)) {
      moved.adjoint[i] = Vector3d::Zero();
      continue;
    }
    const Vector3d a = moved.adjoint[i];
    const Vector3d& n_p = moved.normal[i];
    moved.adjoint[i] = (a - n_p * n_p.dot(a)) / m_length;
  }
  for (std::uint32_t k = face_offsets_[v]; k < face_offsets_[v + 1]; ++k) {
    const Face& f = patch_.faces[vertex_faces_[k]];
    Vector3d u = Vector3d::Zero();
    int corner = 0;
    for (int c = 0; c < 3; ++c) {
      u += moved.adjoint[static_cast<std::size_t>(moved.find(f[static_cast<std::size_t>(c)]))];
      if (f[static_cast<std::size_t>(c)] == v) corner = c;
    }
    const Vector3d& before = position(f[static_cast<std::size_t>((corner + 2) % 3)], v, x);
    const Vector3d& after = position(f[static_cast<std::size_t>((corner + 1) % 3)], v, x);
    g[2] += u.cross(before - after);
  }
}

double ConstraintSolver::relax(std::uint32_t v) {
  const Vector3d measured = patch_.measured[v].cast<double>();
  Vector3d x = x_[v];
  double start = 0.0;  // evaluated once a step is worth trying
  double current = 0.0;
  // Curvature estimate per term, for the step's scale: 2 |n_V|^2 for geometry; about 2 w / L^2
  // per edge for a normal turning by |dx| / L (from each end: 4 w / L^2); 2 w_sem / L^2 for 1 / L.
  double h = 2.0 * patch_.plane_normals[v].cast<double>().squaredNorm();
  for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) {
    const double length = lengths_[k];
    if (!(length > 0.0)) continue;
    const double l3 = length * length * length;
    h += params_.lambda_smooth * 4.0 * neighbours_[k].similarity / l3 +
         params_.lambda_sem * 2.0 * neighbours_[k].semantic / l3;
  }
  if (!(h > 0.0)) h = 1.0;
  bool scratch_at_x = false;  // whether the thread's scratch holds the normals with v at x
  for (int step = 0; step < params_.steps; ++step) {
    std::array<Vector3d, 3> g;
    ConstraintEnergy here;
    evaluate(v, x, step == 0 ? &here : nullptr, &g);
    scratch_at_x = true;
    Vector3d dx = -(g[0] + params_.lambda_sem * g[1] + params_.lambda_smooth * g[2]) / h;
    const double length = dx.norm();
    if (!(length > params_.min_step_m)) break;
    if (step == 0) {
      start = here.total;
      current = start;
    }
    if (length > params_.max_step_m) dx *= params_.max_step_m / length;
    bool accepted = false;
    for (int halving = 0; halving < 4 && !accepted; ++halving, dx *= 0.5) {
      Vector3d trial = x + dx;
      const Vector3d offset = trial - measured;
      if (offset.norm() > params_.max_offset_m) trial = measured + offset * (params_.max_offset_m / offset.norm());
      ConstraintEnergy trial_energy;
      evaluate(v, trial, &trial_energy, nullptr);
      const double e = trial_energy.total;
      scratch_at_x = e < current;
      if (e < current) {
        x = trial;
        current = e;
        accepted = true;
      }
    }
    if (!accepted) break;
  }
  if (!(current < start)) return 0.0;
  x_[v] = x;
  patch_.positions[v] = x.cast<float>();
  if (scratch_at_x) {
    const MovedNormals& moved = movedScratch();
    for (std::size_t i = 0; i < moved.vertex.size(); ++i) {
      area_normals_[moved.vertex[i]] = moved.area[i];
      normals_[moved.vertex[i]] = moved.normal[i];
    }
  } else {
    refreshNormal(v);
    for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) {
      refreshNormal(neighbours_[k].vertex);
    }
  }
  for (std::uint32_t k = neighbour_offsets_[v]; k < neighbour_offsets_[v + 1]; ++k) {
    const std::uint32_t u = neighbours_[k].vertex;
    lengths_[k] = (x_[v] - x_[u]).norm();
    // The same edge in u's list (sorted by vertex; u neighbours an active vertex, so it has one).
    const auto first = neighbours_.begin() + neighbour_offsets_[u];
    const auto last = neighbours_.begin() + neighbour_offsets_[u + 1];
    const auto back =
        std::lower_bound(first, last, v, [](const Neighbour& nb, std::uint32_t w) { return nb.vertex < w; });
    if (back != last && back->vertex == v) lengths_[static_cast<std::size_t>(back - neighbours_.begin())] = lengths_[k];
  }
  return start - current;
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
