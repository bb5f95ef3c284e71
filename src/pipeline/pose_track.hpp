#pragma once
// Internal to the pipeline module: the poses of the frames mapped so far, as the run needs them:
// each frame's prior, what deskewing and registration need of the last mapped frame, and the
// trajectory (a line per frame of the range, mapped or skipped).

#include <cstddef>
#include <optional>
#include <string>

#include "artemis/core/transform.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/registration/odometry.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::pipeline {

class PoseTrack {
 public:
  // Priors come from the recording's motion when `recording_poses`, else from `odometry`'s
  // constant-velocity guess (it must then be given). Both must outlive the track.
  PoseTrack(const datasets::Dataset& dataset, bool recording_poses, const registration::Odometry* odometry)
      : dataset_(dataset), recording_poses_(recording_poses), odometry_(odometry) {}

  // The prior of the range's i-th frame: the recording's motion since the last mapped frame,
  // composed with that frame's (possibly refined) pose; or a constant-velocity guess. Before the
  // first mapped frame: the recording's pose, or the identity.
  [[nodiscard]] Isometry3d prior(std::size_t i) const;

  // Frame i was skipped: its trajectory line is its prior, so that line k stays frame k.
  void skipped(const Isometry3d& prior) { appendLine(prior); }
  // Frame i was mapped at T_W_L.
  void mapped(std::size_t i, const Isometry3d& T_W_L, double stamp_s);

  [[nodiscard]] const std::optional<Isometry3d>& lastPose() const { return last_T_; }
  [[nodiscard]] double lastStamp() const { return last_stamp_s_; }
  // Frames of the range from the last mapped one to the i-th (i before the first).
  [[nodiscard]] int framesSinceLast(std::size_t i) const { return static_cast<int>(i - last_i_); }
  // Row-major 3x4 T_W_L, a line per frame so far.
  [[nodiscard]] const std::string& trajectory() const { return trajectory_; }

  // Checkpoints (stage_checkpoint.cpp).
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  void appendLine(const Isometry3d& T);

  const datasets::Dataset& dataset_;
  bool recording_poses_;
  const registration::Odometry* odometry_;
  std::optional<Isometry3d> last_T_;
  std::size_t last_i_ = 0;
  double last_stamp_s_ = 0.0;
  std::string trajectory_;
};

}  // namespace artemis::pipeline
