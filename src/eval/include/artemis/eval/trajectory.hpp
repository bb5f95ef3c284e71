#pragma once
// Trajectory accuracy against a reference trajectory of the same frames.
//
// Relative pose error over windows of `window` frames: for every i with i + window in range,
// D_i = inv(inv(R_i) R_{i+w}) * (inv(E_i) E_{i+w}), R the reference and E the estimate, compares the estimated motion
// over the window with the reference's; D_i's translation length and rotation angle are summarised. Independent of how
// either trajectory is anchored in its world.
//
// Drift: both trajectories re-anchored at their first frame; the position error of each frame
// divided by the reference path length up to it, as a percentage, at the last frame and at worst
// over frames at least `min_path_m` along.

#include <cstddef>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"

namespace artemis::eval {

struct ErrorStats {
  double mean = 0.0;
  double rmse = 0.0;
  double median = 0.0;
  double max = 0.0;
};

struct RelativePoseError {
  std::size_t window = 0;
  std::size_t pairs = 0;
  ErrorStats translation_m;
  ErrorStats rotation_deg;
};

struct Drift {
  double path_m = 0.0;            // reference path length, first to last frame
  double end_error_m = 0.0;       // position error of the last frame
  double end_percent = 0.0;       // end_error_m / path_m * 100
  double max_percent = 0.0;       // worst error / path so far * 100, over frames >= min_path_m along
  double end_rotation_deg = 0.0;  // orientation error of the last frame
};

// Errors when the trajectories differ in length, or are shorter than window + 1 frames.
Result<RelativePoseError> relativePoseError(const std::vector<Isometry3d>& estimate,
                                            const std::vector<Isometry3d>& reference, std::size_t window);

Result<Drift> drift(const std::vector<Isometry3d>& estimate, const std::vector<Isometry3d>& reference,
                    double min_path_m = 10.0);

}  // namespace artemis::eval
