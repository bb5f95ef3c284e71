#include "artemis/eval/trajectory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace artemis::eval {

namespace {

ErrorStats summarise(std::vector<double> v) {
  ErrorStats s;
  if (v.empty()) return s;
  double sum = 0.0;
  double sq = 0.0;
  for (const double x : v) {
    sum += x;
    sq += x * x;
  }
  const auto n = static_cast<double>(v.size());
  s.mean = sum / n;
  s.rmse = std::sqrt(sq / n);
  std::sort(v.begin(), v.end());
  s.median = v.size() % 2 == 1 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  s.max = v.back();
  return s;
}

Status checkSizes(const std::vector<Isometry3d>& estimate, const std::vector<Isometry3d>& reference,
                  std::size_t least) {
  if (estimate.size() != reference.size()) {
    return invalidArgument(
        fmt::format("the trajectories differ in length: {} poses against {}", estimate.size(), reference.size()));
  }
  if (estimate.size() < least) {
    return invalidArgument(fmt::format("{} poses, fewer than the {} needed", estimate.size(), least));
  }
  return Status::ok();
}

}  // namespace

Result<RelativePoseError> relativePoseError(const std::vector<Isometry3d>& estimate,
                                            const std::vector<Isometry3d>& reference, std::size_t window) {
  if (Status s = checkSizes(estimate, reference, 0); !s.isOk()) return s;
  if (window == 0 || window >= estimate.size()) {
    return invalidArgument(fmt::format("a window of {} frames needs more than {} poses", window, estimate.size()));
  }
  std::vector<double> translation;
  std::vector<double> rotation;
  for (std::size_t i = 0; i + window < estimate.size(); ++i) {
    const Isometry3d motion_ref = reference[i].inverse() * reference[i + window];
    const Isometry3d motion_est = estimate[i].inverse() * estimate[i + window];
    const Isometry3d error = motion_ref.inverse() * motion_est;
    translation.push_back(error.translation().norm());
    rotation.push_back(rotationAngleDeg(error));
  }
  RelativePoseError out;
  out.window = window;
  out.pairs = translation.size();
  out.translation_m = summarise(std::move(translation));
  out.rotation_deg = summarise(std::move(rotation));
  return out;
}

Result<Drift> drift(const std::vector<Isometry3d>& estimate, const std::vector<Isometry3d>& reference,
                    double min_path_m) {
  if (Status s = checkSizes(estimate, reference, 2); !s.isOk()) return s;
  Drift d;
  const Isometry3d est0 = estimate.front().inverse();
  const Isometry3d ref0 = reference.front().inverse();
  double path = 0.0;
  for (std::size_t k = 1; k < reference.size(); ++k) {
    path += (reference[k].translation() - reference[k - 1].translation()).norm();
    const Isometry3d e = est0 * estimate[k];
    const Isometry3d r = ref0 * reference[k];
    const double error = (e.translation() - r.translation()).norm();
    if (path >= min_path_m && path > 0.0) d.max_percent = std::max(d.max_percent, 100.0 * error / path);
    if (k + 1 == reference.size()) {
      d.end_error_m = error;
      d.end_rotation_deg = rotationAngleDeg(r.inverse() * e);
    }
  }
  d.path_m = path;
  d.end_percent = path > 0.0 ? 100.0 * d.end_error_m / path : 0.0;
  return d;
}

}  // namespace artemis::eval
