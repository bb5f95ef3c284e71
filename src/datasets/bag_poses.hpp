#pragma once
// Poses in a ROS bag: the static transforms (/tf_static) as a graph of frames, and an odometry
// topic's samples interpolated in time.

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "artemis/core/transform.hpp"
#include "artemis/datasets/ros_messages.hpp"

namespace artemis::datasets::detail {

// The bag's static transforms; a chain of them between two frames, either way along each edge.
class StaticFrames {
 public:
  void add(const ros::Transform& t);
  // T_from_to: `to` in `from`, or nullopt when no chain links them.
  [[nodiscard]] std::optional<Isometry3d> find(const std::string& from, const std::string& to) const;

 private:
  std::map<std::string, std::vector<std::pair<std::string, Isometry3d>>> edges_;
};

struct OdometrySample {
  double stamp_s = 0.0;
  Isometry3d pose = Isometry3d::Identity();  // the child frame in the odometry's frame
};

// The odometry at time t (samples sorted by stamp): interpolated between the samples around it,
// linearly in position and spherically in rotation; nullopt outside their span (beyond half the
// mean sample period at either end).
std::optional<Isometry3d> odometryAt(const std::vector<OdometrySample>& samples, double t);

}  // namespace artemis::datasets::detail
