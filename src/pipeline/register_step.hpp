#pragma once
// Internal to the pipeline module: what runPipeline does to a frame before mapping it, the
// sweep's motion compensation (RunParams::deskew) and scan-to-map registration
// (RunParams::pose_refinement), with the warnings and counts that go with them.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <utility>

#include "artemis/core/frame.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/registration/odometry.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::pipeline {

class RegisterStep {
 public:
  // `odometry`: the scan-to-map registration, nullptr without pose refinement; it must outlive the
  // step. `recording`: the recording's folder, named in warnings.
  RegisterStep(registration::Odometry* odometry, bool deskew, std::filesystem::path recording)
      : odometry_(odometry), deskew_(deskew), recording_(std::move(recording)) {}

  // Deskews `frame`'s points (with the prior's motion since the last mapped frame, `last_T` taken
  // at `last_stamp_s`; none before the first) and registers them, `frames_since` frames of the
  // range after the last mapped one (taken as 1 before the first). Returns the frame's pose T_W_L: `prior`
  // without pose refinement. Adds the "register" time (where deskewing or registration is on),
  // the registration and its frame, and the fallback and degenerate counts to `report`.
  Isometry3d run(Frame& frame, const Isometry3d& prior, const std::optional<Isometry3d>& last_T, int frames_since,
                 double last_stamp_s, RunReport& report);

  // The scan-to-map registration; nullptr without pose refinement.
  [[nodiscard]] const registration::Odometry* odometry() const { return odometry_; }
  // Frames whose sweep could not be deskewed (each logged).
  [[nodiscard]] std::size_t notDeskewed() const { return not_deskewed_; }

  // Checkpoints (stage_checkpoint.cpp): its counts; the odometry is saved by its owner.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  void deskew(Frame& frame, const Isometry3d& motion, double period_s);

  registration::Odometry* odometry_;
  bool deskew_;
  std::filesystem::path recording_;
  bool warned_no_sweep_ = false;
  std::size_t not_deskewed_ = 0;
};

}  // namespace artemis::pipeline
