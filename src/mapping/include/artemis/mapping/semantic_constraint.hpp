#pragma once
// Stage 1d, the semantic constraint (paper §III-B, eq. 2-8): vertex positions are moved to lower
//
//   E_total = E_geometry + lambda_sem E_semantic + lambda_smooth E_smoothness          (eq. 2)
//
// and faces that join semantically different surfaces across a depth gap are cut. How we read
// each symbol:
//   - E_geometry = sum_v (n_V . (x_v - p_v))^2: point-to-plane distance of vertex v to its local
//     plane, the plane through its LiDAR return p_v whose normal n_V is the PCA normal of its
//     voxel's points (the mesher's plane). Sliding along the surface is free; leaving it is not.
//   - E_semantic = sum over edges (i, j) of w_sem_ij JS(P_i || P_j)                    (eq. 3)
//     with w_sem_ij = xi_i xi_j / L_ij (eq. 6), L_ij = |x_i - x_j|, and xi the vertex confidence of
//     eq. 7, 1 - exp(-lambda W_sem) with W_sem its voxel's accumulated observation weight. P is
//     the vertex's class distribution over the run's slots (uniform when never observed, so the
//     term vanishes on a run without masks). JS is in nats, in [0, ln 2]. Through 1 / L_ij it
//     pushes apart neighbours whose distributions differ: the boundary between two objects opens.
//   - E_smoothness = sum over edges (i, j) of w_smooth_ij |n_i - n_j|^2                 (eq. 4)
//     with w_smooth_ij = sim_ij w_geo_ij (eq. 8), sim_ij = exp(-tau sqrt(JS_ij)) (eq. 5) and
//     w_geo_ij = 1 / L_ij (inverse edge length, as the paper suggests). n_i is the vertex normal:
//     the normalised sum of its faces' area vectors, so it depends on the positions of the vertex
//     and its neighbours. Eq. 4 sums each edge from both ends; we sum it once (a factor 2 that
//     lambda_smooth absorbs). Across a semantic boundary sim is small: the crease stays sharp.
//   - Distributions do not change while positions are optimised, so JS and sim are constants of
//     each solve.
//
// Solver: non-linear Gauss-Seidel over the active vertices (those of the voxels meshed this
// frame). For each vertex, with every other vertex fixed, a few damped gradient steps on the part
// of E_total that depends on it (its geometry term, its edges, and the edges of every vertex whose
// normal it changes), scaled by a curvature estimate and accepted only when they lower that part:
// so every sweep lowers E_total. Sweeps stop when one lowers E_total by less than `tolerance` of
// its value, or after `max_sweeps`. A vertex never moves farther than max_offset_m from its LiDAR
// return (the step is projected back onto that ball), so a vertex far from its voxel's points
// cannot drift.
//
// The problem is a patch: the faces of the frame's meshed voxels and of their neighbours, so the
// cost grows with the active vertices, not with the map. Normals of vertices at the patch's edge
// are taken over the patch's faces.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_key.hpp"

namespace artemis::mapping {

class VoxelMap;

struct SemanticConstraintParams {
  bool enabled = true;
  double lambda_sem = 1e-4;     // lambda_sem of eq. 2
  double lambda_smooth = 2e-3;  // lambda_smooth of eq. 2
  double temperature = 4.0;     // tau of eq. 5
  // One sweep: on the simulated street (200 frames, noise 0.03 m) a second lowered the vertices' RMS
  // distance to the true surface only from 14.7 to 14.4 mm, for 4-5 ms more a frame.
  int max_sweeps = 1;
  double tolerance = 1e-3;     // relative decrease of E_total below which sweeps stop
  int steps = 1;               // damped steps per vertex and sweep
  double min_step_m = 1e-4;    // a vertex whose step would be shorter is left where it is
  double max_step_m = 0.02;    // longest single step
  double max_offset_m = 0.05;  // farthest a vertex may move from its LiDAR return
  // Topology: a face is cut when one of its edges has sim below cut_similarity and spans more
  // than cut_depth_gap_m along the viewing ray (a car and the road behind or under it). On the
  // simulated street (200 frames, noise 0.03 m, standard masks), against 80 faces joining car and
  // road and F1 at 0.1 m of 0.9283 without the constraint, (gap, sim) = (0.05, 0.3) cut 64,543
  // faces and left 34 car-road faces at F1 0.9255; (0.05, 0.1) cut 13,077, left 35, F1 0.9273;
  // (0.05, 0.05) cut 7,582 and left 46; (0.1, 0.1) left 55; no cut left 81 at F1 0.9285. Earlier:
  // (0.1, 0.5) 53 faces; (0.15, 0.2) 71. Similarities between 0.1 and 0.3 are mostly noisy masks on
  // one surface, not two objects.
  double cut_similarity = 0.1;
  double cut_depth_gap_m = 0.05;
};

// The arrays a solve works on: vertices of a patch (local indices) and its faces.
struct ConstraintPatch {
  std::vector<Eigen::Vector3f> positions;      // x, moved in place by the solver
  std::vector<Eigen::Vector3f> measured;       // p, the LiDAR returns
  std::vector<Eigen::Vector3f> plane_normals;  // n_V, unit; zero: no geometry term for the vertex
  std::vector<float> confidence;               // xi (eq. 7)
  std::size_t slots = 1;
  std::vector<float> distributions;  // slots values per vertex, each summing to 1
  std::vector<Face> faces;
  std::vector<std::uint8_t> active;  // 1: the vertex may move
  // Optional, for a parallel sweep: per vertex a block id and the block's colour (0..7). Blocks of
  // one colour are solved in parallel, colours one after the other, a block's vertices in index
  // order; the caller guarantees that vertices of two blocks of the same colour never share a term
  // or a neighbour's normal (more than three edges apart), so the result does not depend on the
  // thread count. Empty: one sequential sweep in index order.
  std::vector<VoxelKey> block;
  std::vector<std::uint8_t> colour;
};

// The three energies of eq. 2, unweighted, and their weighted sum.
struct ConstraintEnergy {
  double geometry = 0.0;
  double semantic = 0.0;
  double smoothness = 0.0;
  double total = 0.0;
};

struct ConstraintStats {
  double ms = 0.0;
  double patch_ms = 0.0;  // of ms: gathering the patch
  double build_ms = 0.0;  // its adjacency and each edge's JS and sim
  double solve_ms = 0.0;  // the sweeps
  std::size_t active_vertices = 0;
  std::size_t patch_vertices = 0;
  int sweeps = 0;
  double energy_before = 0.0;
  double energy_after = 0.0;
  std::size_t faces_cut = 0;
};

// Jensen-Shannon divergence of two distributions over n slots, in nats (0 .. ln 2).
double jensenShannon(const float* p, const float* q, std::size_t n);
// sim of eq. 5: exp(-tau sqrt(JS)).
inline double semanticSimilarity(double js, double temperature) {
  return std::exp(-temperature * std::sqrt(js));
}

class ConstraintSolver {
 public:
  // Builds the patch's adjacency and each edge's JS and sim. Throws std::invalid_argument when the
  // arrays disagree in size or a face names a vertex out of range.
  ConstraintSolver(const SemanticConstraintParams& params, ConstraintPatch& patch);

  // E_total of the patch, less the edges between two vertices that neither move nor neighbour one
  // that moves (constants of the solve).
  [[nodiscard]] ConstraintEnergy energy() const;
  // The part of E_total that depends on vertex v's position (what a Gauss-Seidel step lowers):
  // E_total(x) - localEnergy(v, x) does not depend on x. Terms unweighted, total weighted. v must be
  // active or next to an active vertex (else std::invalid_argument), as must localGradient's.
  [[nodiscard]] ConstraintEnergy localEnergy(std::uint32_t v, const Eigen::Vector3d& x) const;
  // Analytic gradients of the three terms of localEnergy(v, x) with respect to x, unweighted.
  [[nodiscard]] std::array<Eigen::Vector3d, 3> localGradient(std::uint32_t v, const Eigen::Vector3d& x) const;
  // One sweep over the active vertices (see ConstraintPatch::block); returns how much it lowered
  // E_total.
  double sweep();
  // Sweeps until the tolerance or the sweep limit; fills stats' sweeps and energies.
  void solve(ConstraintStats& stats);

 private:
  struct Neighbour {
    std::uint32_t vertex;
    float similarity;  // sim of eq. 5
    float semantic;    // xi_i xi_j JS_ij, the numerator of eq. 3's term
  };
  [[nodiscard]] const Eigen::Vector3d& position(std::uint32_t v, std::uint32_t moved, const Eigen::Vector3d& x) const {
    return v == moved ? x : x_[v];
  }
  // |x_p - x_q| for neighbour entry k (q in p's list), with vertex `moved` at x: cached unless the
  // edge has `moved` at an end.
  [[nodiscard]] double edgeLength(std::uint32_t p, std::uint32_t q, std::uint32_t k, std::uint32_t moved,
                                  const Eigen::Vector3d& x) const {
    return p == moved || q == moved ? (position(p, moved, x) - position(q, moved, x)).norm() : lengths_[k];
  }
  // Unnormalised normal of v (sum of its faces' area vectors), with vertex `moved` at x.
  [[nodiscard]] Eigen::Vector3d areaNormal(std::uint32_t v, std::uint32_t moved, const Eigen::Vector3d& x) const;
  void refreshNormal(std::uint32_t v);
  // The constructor's steps, in order.
  void indexFaces();
  void gatherNeighbours();
  void startGeometry();
  void orderPhases();
  void checkMovable(std::uint32_t v) const;
  // localEnergy and localGradient together (either may be null), sharing the moved normals.
  void evaluate(std::uint32_t v, const Eigen::Vector3d& x, ConstraintEnergy* energy,
                std::array<Eigen::Vector3d, 3>* gradient) const;
  // Damped steps on vertex v; returns how much they lowered E_total.
  double relax(std::uint32_t v);

  SemanticConstraintParams params_;
  ConstraintPatch& patch_;
  std::vector<std::uint32_t> face_offsets_;  // vertex -> faces (CSR)
  std::vector<std::uint32_t> vertex_faces_;
  std::vector<std::uint32_t> neighbour_offsets_;  // vertex -> neighbours (CSR, sorted)
  std::vector<Neighbour> neighbours_;
  std::vector<double> lengths_;                // per neighbour entry: the edge's length at the current positions
  std::vector<Eigen::Vector3d> x_;             // positions, in double
  std::vector<Eigen::Vector3d> area_normals_;  // m_v at the current positions
  std::vector<Eigen::Vector3d> normals_;       // n_v = m_v / |m_v| (zero when |m_v| is 0)
  // The sweep's schedule: phases run one after the other; a phase's groups may run in parallel.
  std::vector<std::vector<std::vector<std::uint32_t>>> phases_;
};

// The mapper's stage 1d: cuts and solves the patch around the voxels meshed this frame.
class SemanticConstraint {
 public:
  // `confidence_lambda` is eq. 7's lambda, semantic fusion's setting. Throws std::invalid_argument
  // for a weight, temperature, step or offset that is negative or not finite, or no sweep or step.
  SemanticConstraint(const SemanticConstraintParams& params, double confidence_lambda);

  // Whether face f should be cut: an edge of f joins semantically different vertices (sim below
  // cut_similarity) across a depth gap. Read-only; safe from many threads.
  [[nodiscard]] bool cuts(const SemanticMesh& mesh, const Face& f) const;
  // Solves the patch of the voxels `meshed` (their vertices move; the faces of their neighbours
  // take part with fixed vertices) and writes the new positions into `mesh`.
  ConstraintStats apply(const VoxelMap& map, SemanticMesh& mesh, const std::vector<VoxelKey>& meshed);

  [[nodiscard]] const SemanticConstraintParams& params() const { return params_; }

 private:
  SemanticConstraintParams params_;
  double confidence_lambda_;
  // Per mesh vertex, for the current solve (stamp): its level, valid where stamp_ matches (1 active,
  // 2 a neighbour of an active vertex, 0 only a corner of a patch face), and its patch index, valid
  // where numbered_ matches.
  std::vector<std::uint8_t> level_;
  std::vector<std::uint32_t> stamp_;
  std::vector<std::uint32_t> local_of_;
  std::vector<std::uint32_t> numbered_;
  std::uint32_t current_stamp_ = 0;
};

}  // namespace artemis::mapping
