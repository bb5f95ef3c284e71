// The semantic constraint solver's local step (semantic_constraint.hpp): the part of E_total that
// depends on one vertex, its analytic gradient, and the damped Gauss-Seidel steps that lower it.
#include "artemis/mapping/semantic_constraint.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace artemis::mapping {

using Eigen::Vector3d;

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

}  // namespace artemis::mapping
