#include "artemis/mapping/hole_filling.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <unordered_set>

#include <Eigen/Geometry>

#include "artemis/core/timer.hpp"

namespace artemis::mapping {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

std::uint64_t edgeKey(std::uint32_t from, std::uint32_t to) {
  return (std::uint64_t{from} << 32) | to;
}

// A face's edge, keyed by its two vertices (smaller first) so that both directions sort together.
// Twelve bytes rather than sixteen: the run's finish indexes every face still in memory.
struct HalfEdge {
  std::uint32_t lo;
  std::uint32_t hi;
  std::uint32_t face_forward;  // face << 1, | 1 when the edge runs from lo to hi

  HalfEdge(std::uint32_t lo_vertex, std::uint32_t hi_vertex, std::uint32_t face, bool forward)
      : lo(lo_vertex), hi(hi_vertex), face_forward((face << 1) | (forward ? 1u : 0u)) {}
  [[nodiscard]] std::uint32_t face() const { return face_forward >> 1; }
  [[nodiscard]] bool forward() const { return (face_forward & 1u) != 0; }
  [[nodiscard]] bool sameEdge(const HalfEdge& o) const { return lo == o.lo && hi == o.hi; }
  bool operator<(const HalfEdge& o) const { return lo != o.lo ? lo < o.lo : hi < o.hi; }
};

struct BoundaryEdge {
  std::uint32_t from;
  std::uint32_t to;
  std::uint32_t face;
};

class HoleFiller {
 public:
  HoleFiller(const std::vector<Face>& faces, const std::vector<Eigen::Vector3f>& positions, double max_edge_m,
             const HoleFillParams& params)
      : faces_(faces), positions_(positions), max_edge_m_(max_edge_m), params_(params) {}

  std::vector<Face> run(HoleFillStats& stats) {
    indexHalfEdges();
    findBoundary();
    stats.boundary_edges = boundary_.size();
    std::vector<Face> fills;
    std::vector<std::uint8_t> visited(boundary_.size(), 0);
    for (std::size_t start = 0; start < boundary_.size(); ++start) {
      if (visited[start] != 0) continue;
      const std::optional<std::vector<std::size_t>> loop = trace(start, visited);
      if (!loop) continue;
      ++stats.loops;
      const std::size_t before = fills.size();
      if (close(*loop, fills, stats)) ++stats.filled;
      stats.faces += fills.size() - before;
    }
    return fills;
  }

 private:
  // Every face's three edges, sorted by their vertex pair.
  void indexHalfEdges() {
    if (faces_.size() >= (std::size_t{1} << 31)) throw std::length_error("hole filling: too many faces");
    half_edges_.reserve(faces_.size() * 3);
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      const Face& t = faces_[f];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t from = t[k];
        const std::uint32_t to = t[(k + 1) % 3];
        half_edges_.emplace_back(std::min(from, to), std::max(from, to), static_cast<std::uint32_t>(f), from < to);
      }
    }
    tbb::parallel_sort(half_edges_.begin(), half_edges_.end());
  }

  // Whether a face of the mesh has the edge from -> to.
  [[nodiscard]] bool inMesh(std::uint32_t from, std::uint32_t to) const {
    const HalfEdge edge(std::min(from, to), std::max(from, to), 0, false);
    for (auto it = std::lower_bound(half_edges_.begin(), half_edges_.end(), edge);
         it != half_edges_.end() && it->sameEdge(edge); ++it) {
      if (it->forward() == (from < to)) return true;
    }
    return false;
  }

  // Edges that one face uses and no other, in either direction; sorted by their first vertex. (An
  // edge that two faces use in the same direction, where two voxels wound one strip differently,
  // is no hole's edge.)
  void findBoundary() {
    for (std::size_t i = 0; i < half_edges_.size();) {
      std::size_t j = i + 1;
      while (j < half_edges_.size() && half_edges_[j].sameEdge(half_edges_[i])) ++j;
      const HalfEdge& e = half_edges_[i];
      if (j == i + 1 && e.lo != e.hi)
        boundary_.push_back(e.forward() ? BoundaryEdge{e.lo, e.hi, e.face()} : BoundaryEdge{e.hi, e.lo, e.face()});
      i = j;
    }
    std::sort(boundary_.begin(), boundary_.end(), [](const BoundaryEdge& a, const BoundaryEdge& b) {
      return a.from != b.from ? a.from < b.from : a.to < b.to;
    });
  }

  // The boundary edges leaving `vertex`: [first, last) of boundary_.
  [[nodiscard]] std::pair<std::size_t, std::size_t> leaving(std::uint32_t vertex) const {
    const auto by_from = [](const BoundaryEdge& e, std::uint32_t v) { return e.from < v; };
    const auto first = std::lower_bound(boundary_.begin(), boundary_.end(), vertex, by_from);
    auto last = first;
    while (last != boundary_.end() && last->from == vertex) ++last;
    return {static_cast<std::size_t>(first - boundary_.begin()), static_cast<std::size_t>(last - boundary_.begin())};
  }

  // Where two holes (or a hole and the mesh's outline) touch at a vertex, more than one boundary
  // edge leaves it. Faces lie left of their boundary edges (seen from the front), the hole right:
  // the edge that goes on around the same hole is the first one met turning counter-clockwise
  // from the edge we came by, in the plane of that edge's face.
  [[nodiscard]] std::optional<std::size_t> nextAround(std::size_t in, const std::vector<std::uint8_t>& visited) const {
    const auto [first, last] = leaving(boundary_[in].to);
    std::optional<std::size_t> best;
    if (last - first == 1) {
      if (visited[first] == 0) best = first;
      return best;
    }
    const Vector3d v = at(boundary_[in].to);
    const Vector3d back = at(boundary_[in].from) - v;
    const Vector3d n = faceNormal(boundary_[in].face);
    double best_angle = 0.0;
    for (std::size_t k = first; k < last; ++k) {
      if (visited[k] != 0) continue;
      const Vector3d out = at(boundary_[k].to) - v;
      double angle = std::atan2(n.dot(back.cross(out)), back.dot(out));
      if (angle <= 0.0) angle += 2.0 * std::numbers::pi;
      if (!best || angle < best_angle) {
        best = k;
        best_angle = angle;
      }
    }
    return best;
  }

  // Follows boundary edges from `start` until it comes back (the loop's edges, in order) or runs
  // past max_loop_edges.
  std::optional<std::vector<std::size_t>> trace(std::size_t start, std::vector<std::uint8_t>& visited) const {
    std::vector<std::size_t> loop{start};
    for (;;) {
      visited[loop.back()] = 1;
      if (boundary_[loop.back()].to == boundary_[start].from) break;
      if (static_cast<int>(loop.size()) >= params_.max_loop_edges) return std::nullopt;
      const std::optional<std::size_t> on = nextAround(loop.back(), visited);
      if (!on) return std::nullopt;
      loop.push_back(*on);
    }
    if (loop.size() < 3) return std::nullopt;
    // A loop through one vertex twice (two holes touching there) is two holes, not one.
    std::vector<std::uint32_t> corners;
    for (const std::size_t e : loop) corners.push_back(boundary_[e].from);
    std::sort(corners.begin(), corners.end());
    if (std::adjacent_find(corners.begin(), corners.end()) != corners.end()) return std::nullopt;
    return loop;
  }

  static bool reject(std::size_t& reason) {
    ++reason;
    return false;
  }

  [[nodiscard]] Vector3d at(std::uint32_t v) const { return positions_[v].cast<double>(); }

  [[nodiscard]] Vector3d faceNormal(std::uint32_t f) const {
    const Face& t = faces_[f];
    const Vector3d n = (at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0]));
    const double length = n.norm();
    return length > 0.0 ? Vector3d(n / length) : Vector3d::Zero();
  }

  // Closes `edges` (a loop of boundary edges) when it is a small, flat hole; appends the faces to
  // `fills`.
  bool close(const std::vector<std::size_t>& edges, std::vector<Face>& fills, HoleFillStats& stats) {
    const std::size_t n = edges.size();
    std::vector<std::uint32_t> loop(n);
    for (std::size_t i = 0; i < n; ++i) loop[i] = boundary_[edges[i]].from;
    Vector3d centre = Vector3d::Zero();
    for (const std::uint32_t v : loop) centre += at(v);
    centre /= static_cast<double>(n);
    Vector3d area = Vector3d::Zero();  // Newell: along the loop's own normal
    Vector3d around = Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const Vector3d a = at(loop[i]) - centre;
      const Vector3d b = at(loop[(i + 1) % n]) - centre;
      if ((b - a).norm() > max_edge_m_) return reject(stats.long_edges);
      area += a.cross(b);
      around += faceNormal(boundary_[edges[i]].face);
    }
    // A hole's boundary runs against the faces around it: its area vector points away from them.
    const double area_length = area.norm();
    const double around_length = around.norm();
    // The faces around say which way the surface faces: a crack is a sliver whose own area vector
    // is too short to say it under the points' noise.
    if (!(area_length > 0.0) || !(around_length > 0.0)) return reject(stats.unclipped);
    const Vector3d front = around / around_length;
    if (area.dot(front) >= 0.0) return reject(stats.islands);
    if (around_length < params_.min_normal_agreement * static_cast<double>(n)) return reject(stats.rough);
    for (const std::uint32_t v : loop) {
      if (std::abs((at(v) - centre).dot(front)) > params_.max_plane_distance_m) return reject(stats.bumpy);
    }
    std::vector<Face> faces;
    if (!earClip(loop, centre, front, faces)) return reject(stats.unclipped);
    for (const Face& f : faces) {
      for (std::size_t k = 0; k < 3; ++k) {
        if (inMesh(f[k], f[(k + 1) % 3]) || added_.contains(edgeKey(f[k], f[(k + 1) % 3]))) {
          return reject(stats.unclipped);
        }
      }
    }
    for (const Face& f : faces) {
      for (std::size_t k = 0; k < 3; ++k) added_.insert(edgeKey(f[k], f[(k + 1) % 3]));
      fills.push_back(f);
    }
    return true;
  }

  // Triangulates the loop, reversed so that it runs counter-clockwise about `front`, by cutting
  // the ear with the shortest new edge each time. False where it cannot (a loop that crosses
  // itself in its plane) or a face would have an edge longer than max_edge_m.
  bool earClip(const std::vector<std::uint32_t>& loop, const Vector3d& centre, const Vector3d& front,
               std::vector<Face>& out) const {
    const Vector3d u = front.unitOrthogonal();
    const Vector3d w = front.cross(u);
    std::vector<std::uint32_t> ring(loop.rbegin(), loop.rend());
    std::vector<Vector2d> p(ring.size());
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Vector3d d = at(ring[i]) - centre;
      p[i] = {d.dot(u), d.dot(w)};
    }
    std::vector<std::size_t> left(ring.size());
    for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
    const auto cross = [](const Vector2d& a, const Vector2d& b, const Vector2d& c) {
      return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    };
    while (left.size() > 3) {
      const std::size_t m = left.size();
      std::optional<std::size_t> best;
      double best_length = max_edge_m_;
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t a = left[(k + m - 1) % m];
        const std::size_t b = left[k];
        const std::size_t c = left[(k + 1) % m];
        if (!(cross(p[a], p[b], p[c]) > 0.0)) continue;  // reflex or flat corner
        bool empty = true;
        for (const std::size_t q : left) {
          if (q == a || q == b || q == c) continue;
          if (cross(p[a], p[b], p[q]) >= 0.0 && cross(p[b], p[c], p[q]) >= 0.0 && cross(p[c], p[a], p[q]) >= 0.0) {
            empty = false;
            break;
          }
        }
        const double length = (at(ring[a]) - at(ring[c])).norm();
        if (empty && length <= best_length) {
          best = k;
          best_length = length;
        }
      }
      if (!best) return false;
      const std::size_t k = *best;
      out.push_back({ring[left[(k + m - 1) % m]], ring[left[k]], ring[left[(k + 1) % m]]});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(k));
    }
    if (!(cross(p[left[0]], p[left[1]], p[left[2]]) > 0.0)) return false;
    out.push_back({ring[left[0]], ring[left[1]], ring[left[2]]});
    return true;
  }

  const std::vector<Face>& faces_;
  const std::vector<Eigen::Vector3f>& positions_;
  double max_edge_m_;
  HoleFillParams params_;
  std::vector<HalfEdge> half_edges_;
  std::vector<BoundaryEdge> boundary_;  // sorted by `from`
  std::unordered_set<std::uint64_t> added_;
};

}  // namespace

std::vector<Face> holeFillingFaces(const std::vector<Face>& faces, const std::vector<Eigen::Vector3f>& positions,
                                   double max_edge_m, const HoleFillParams& params, HoleFillStats* stats) {
  HoleFillStats local;
  HoleFillStats& s = stats != nullptr ? *stats : local;
  s = {};
  if (!params.enabled) return {};
  Stopwatch clock;
  HoleFiller filler(faces, positions, max_edge_m, params);
  std::vector<Face> fills = filler.run(s);
  s.ms = clock.elapsedMs();
  return fills;
}

}  // namespace artemis::mapping
