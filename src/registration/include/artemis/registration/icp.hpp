#pragma once
// Point-to-plane ICP of a scan against a LocalMap: Gauss-Newton on SE(3) with a Geman-McClure
// robust kernel, coarse to fine over correspondence distances.
//
// Reading of the solver: a source point p (LiDAR frame) maps to p_W = T p. Its correspondence is
// the nearest map point q with normal n within the stage's distance d; the residual is
// r = n . (p_W - q). The update perturbs the pose about the sensor's current position c:
// p_W' = p_W + w x (p_W - c) + v, so the Jacobian row is [((p_W - c) x n)^T, n^T] and rotation and
// translation stay decoupled however far the sensor is from the world origin. Each residual is
// weighted by Geman-McClure's w(r) = s^4 / (s^2 + r^2)^2 with scale s = max(d * kernel_ratio,
// min_kernel_m).
//
// Degeneracy: the normal equations are scaled to common units (rotation times `lever_m`, a typical
// point range, against translation) and split by eigen-decomposition; directions whose share of the
// constraint falls below `degenerate_eigen_ratio` are not updated, so there the prior is kept (a
// corridor's long axis, a single wall's in-plane directions). The result says how many there were.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/transform.hpp"
#include "artemis/registration/local_map.hpp"

namespace artemis::registration {

struct IcpParams {
  // Stage k gates correspondences at d_k = max(first_distance / 2^k, min_distance_m), and stops
  // after the stage that reached min_distance_m. The gate is Euclidean, to the nearest map point,
  // so it must stay above the map's point spacing; the residual is weighed by the robust kernel
  // with scale max(d_k * kernel_ratio, min_kernel_m).
  double min_distance_m = 0.5;
  double kernel_ratio = 0.25;
  double min_kernel_m = 0.05;
  int max_iterations = 30;  // per stage
  // A stage ends when a step moves less than this (coarse stages: ten times more).
  double converged_translation_m = 5e-4;
  double converged_rotation_rad = 5e-5;
  // Correspondences are searched again once the pose moved this much (translation plus rotation
  // times lever_m) since the last search; in between, Gauss-Newton steps reuse them.
  double research_motion_m = 0.01;
  int min_correspondences = 100;  // fewer: the prior is kept
  double lever_m = 10.0;
  // A direction is degenerate when its eigenvalue is below this share of the largest.
  double degenerate_eigen_ratio = 1e-3;
};

struct IcpResult {
  Isometry3d T_W_L = Isometry3d::Identity();
  int iterations = 0;
  std::size_t correspondences = 0;  // in the last iteration
  double rms_m = 0.0;               // of the last iteration's point-to-plane residuals
  bool converged = false;
  int degenerate_directions = 0;  // of 6, in the last iteration
  bool used_prior = false;        // too few correspondences: T_W_L is the initial guess
};

// Aligns `source_L` (LiDAR frame) to `map`, starting from `initial_T_W_L`, with the first stage's
// correspondence distance `first_distance_m`. When a stage finds fewer than min_correspondences,
// the result of the stages before it stands (the prior, if there were none). Runs on the calling TBB arena; results do
// not depend on the thread count (fixed chunks, summed in order).
IcpResult alignToMap(const std::vector<Eigen::Vector3f>& source_L, const LocalMap& map, const Isometry3d& initial_T_W_L,
                     double first_distance_m, const IcpParams& params);

}  // namespace artemis::registration
