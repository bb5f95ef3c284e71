#include "pose_track.hpp"

namespace artemis::pipeline {

Isometry3d PoseTrack::prior(std::size_t i) const {
  if (!last_T_) return recording_poses_ ? dataset_.pose(i) : Isometry3d::Identity();
  if (recording_poses_) return *last_T_ * dataset_.pose(last_i_).inverse() * dataset_.pose(i);
  return odometry_->predictConstantVelocity(framesSinceLast(i));
}

void PoseTrack::mapped(std::size_t i, const Isometry3d& T_W_L, double stamp_s) {
  appendLine(T_W_L);
  last_T_ = T_W_L;
  last_i_ = i;
  last_stamp_s_ = stamp_s;
}

void PoseTrack::appendLine(const Isometry3d& T) {
  trajectory_ += formatRowMajor3x4(T);
  trajectory_ += '\n';
}

}  // namespace artemis::pipeline
