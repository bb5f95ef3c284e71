#include "artemis/registration/icp.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace artemis::registration {

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct Normal {
  Matrix6d hessian = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  double weighted_sq = 0.0;
  double weight = 0.0;
  std::size_t count = 0;

  Normal& operator+=(const Normal& o) {
    hessian += o.hessian;
    g += o.g;
    weighted_sq += o.weighted_sq;
    weight += o.weight;
    count += o.count;
    return *this;
  }
};

constexpr std::size_t kChunk = 256;

struct Match {
  Eigen::Vector3f point;
  Eigen::Vector3f normal;
  bool found = false;
};

// Nearest map surfel of every source point at pose T, within `distance`.
void findMatches(const std::vector<Eigen::Vector3f>& source_L, const LocalMap& map, const Isometry3d& T, float distance,
                 std::vector<Match>& matches) {
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  matches.resize(source_L.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, source_L.size(), kChunk), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const auto match = map.nearest(R * source_L[i] + t, distance);
      matches[i].found = match.has_value();
      if (match) {
        matches[i].point = match->point;
        matches[i].normal = match->normal;
      }
    }
  });
}

// Builds the normal equations of one Gauss-Newton step: fixed chunks summed in order, so the sum
// does not depend on how many threads ran them.
Normal buildNormalEquations(const std::vector<Eigen::Vector3f>& source_L, const std::vector<Match>& matches,
                            const Isometry3d& T, double kernel_scale, std::vector<Normal>& chunks) {
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d c = T.translation();
  const double s2 = kernel_scale * kernel_scale;
  const std::size_t n_chunks = (source_L.size() + kChunk - 1) / kChunk;
  chunks.assign(n_chunks, Normal{});
  tbb::parallel_for(std::size_t{0}, n_chunks, [&](std::size_t chunk) {
    Normal& out = chunks[chunk];
    const std::size_t end = std::min(source_L.size(), (chunk + 1) * kChunk);
    for (std::size_t i = chunk * kChunk; i < end; ++i) {
      if (!matches[i].found) continue;
      const Eigen::Vector3d n = matches[i].normal.cast<double>();
      const Eigen::Vector3d arm = R * source_L[i].cast<double>();  // p_W - c
      const double r = n.dot(arm + c - matches[i].point.cast<double>());
      Vector6d jacobian;
      jacobian.head<3>() = arm.cross(n);
      jacobian.tail<3>() = n;
      const double denom = s2 + r * r;
      const double w = s2 * s2 / (denom * denom);  // Geman-McClure, 1 at r = 0
      out.hessian.selfadjointView<Eigen::Upper>().rankUpdate(jacobian, w);
      out.g += w * r * jacobian;
      out.weighted_sq += w * r * r;
      out.weight += w;
      ++out.count;
    }
  });
  Normal total;
  for (const Normal& part : chunks) total += part;
  total.hessian = total.hessian.selfadjointView<Eigen::Upper>();
  return total;
}

}  // namespace

IcpResult alignToMap(const std::vector<Eigen::Vector3f>& source_L, const LocalMap& map, const Isometry3d& initial_T_W_L,
                     double first_distance_m, const IcpParams& params) {
  IcpResult result;
  result.T_W_L = initial_T_W_L;
  if (source_L.empty() || map.empty()) {
    result.used_prior = true;
    return result;
  }
  Isometry3d T = initial_T_W_L;
  std::vector<Normal> chunks;
  std::vector<Match> matches;
  // Scaling to common units: x_s = S^-1 x with rotation in radians times lever_m.
  Vector6d scale;
  scale << Eigen::Vector3d::Constant(1.0 / params.lever_m), Eigen::Vector3d::Ones();
  bool solved = false;  // at least one Gauss-Newton step was taken
  const double first = std::max(first_distance_m, params.min_distance_m);
  for (int stage = 0;; ++stage) {
    const Isometry3d stage_start = T;
    const double distance = std::max(first / std::pow(2.0, stage), params.min_distance_m);
    const bool last_stage = distance <= params.min_distance_m;
    const double kernel = std::max(distance * params.kernel_ratio, params.min_kernel_m);
    const double tolerance = last_stage ? 1.0 : 10.0;
    bool starved = false;
    double moved = 0.0;  // since the correspondences were last searched, at lever_m
    for (int it = 0; it < params.max_iterations; ++it) {
      if (it == 0 || moved > params.research_motion_m) {
        findMatches(source_L, map, T, static_cast<float>(distance), matches);
        moved = 0.0;
      }
      const Normal eq = buildNormalEquations(source_L, matches, T, kernel, chunks);
      ++result.iterations;
      if (eq.count < static_cast<std::size_t>(params.min_correspondences)) {
        if (!solved) result.correspondences = eq.count;  // for the caller's log
        // The stage lost its matches (a finer one would find even fewer): what the stages before
        // it gave stands.
        starved = true;
        T = stage_start;
        break;
      }
      solved = true;
      result.correspondences = eq.count;
      result.rms_m = eq.weight > 0.0 ? std::sqrt(eq.weighted_sq / eq.weight) : 0.0;
      // Solve in scaled units, only along well-constrained eigen-directions.
      const Matrix6d hessian_scaled = scale.asDiagonal() * eq.hessian * scale.asDiagonal();
      const Vector6d gs = scale.asDiagonal() * eq.g;
      Eigen::SelfAdjointEigenSolver<Matrix6d> eig(hessian_scaled);
      const Vector6d& lambda = eig.eigenvalues();
      const double floor = params.degenerate_eigen_ratio * lambda.maxCoeff();
      Vector6d step_s = Vector6d::Zero();
      int degenerate = 0;
      for (int k = 0; k < 6; ++k) {
        if (!(lambda(k) > floor)) {
          ++degenerate;
          continue;
        }
        const Vector6d v = eig.eigenvectors().col(k);
        step_s -= v * (v.dot(gs) / lambda(k));
      }
      result.degenerate_directions = degenerate;
      const Vector6d step = scale.asDiagonal() * step_s;
      const Eigen::Vector3d w = step.head<3>();
      const Eigen::Vector3d v = step.tail<3>();
      // p' = Exp(w) (p - c) + c + v: rotation about the sensor, then translation.
      const double angle = w.norm();
      const Eigen::Matrix3d delta_rotation =
          angle > 0.0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
      Isometry3d next = Isometry3d::Identity();
      next.linear() = delta_rotation * T.linear();
      next.translation() = T.translation() + v;
      // Re-orthonormalise against drift over many small products.
      next.linear() = Eigen::Quaterniond(next.linear()).normalized().toRotationMatrix();
      T = next;
      moved += v.norm() + params.lever_m * angle;
      result.converged =
          v.norm() < tolerance * params.converged_translation_m && angle < tolerance * params.converged_rotation_rad;
      if (result.converged) break;
    }
    if (starved || last_stage) break;
  }
  if (!solved) {
    result.used_prior = true;
    result.T_W_L = initial_T_W_L;
    return result;
  }
  result.T_W_L = T;
  return result;
}

}  // namespace artemis::registration
