#include "bag_poses.hpp"

#include <algorithm>
#include <deque>

#include <Eigen/Geometry>

namespace artemis::datasets::detail {

void StaticFrames::add(const ros::Transform& t) {
  edges_[t.header.frame_id].push_back({t.child_frame_id, t.T_parent_child});
  edges_[t.child_frame_id].push_back({t.header.frame_id, t.T_parent_child.inverse()});
}

std::optional<Isometry3d> StaticFrames::find(const std::string& from, const std::string& to) const {
  std::map<std::string, Isometry3d> seen{{from, Isometry3d::Identity()}};
  std::deque<std::string> queue{from};
  while (!queue.empty()) {
    const std::string at = queue.front();
    queue.pop_front();
    if (at == to) return seen.at(at);
    const auto it = edges_.find(at);
    if (it == edges_.end()) continue;
    for (const auto& [next, T_at_next] : it->second) {
      if (seen.contains(next)) continue;
      seen.emplace(next, seen.at(at) * T_at_next);
      queue.push_back(next);
    }
  }
  return std::nullopt;
}

std::optional<Isometry3d> odometryAt(const std::vector<OdometrySample>& samples, double t) {
  if (samples.empty()) return std::nullopt;
  const double slack = samples.size() > 1 ? 0.5 * (samples.back().stamp_s - samples.front().stamp_s) /
                                                static_cast<double>(samples.size() - 1)
                                          : 0.0;
  if (t < samples.front().stamp_s - slack || t > samples.back().stamp_s + slack) return std::nullopt;
  const auto after = std::lower_bound(samples.begin(), samples.end(), t,
                                      [](const OdometrySample& s, double v) { return s.stamp_s < v; });
  if (after == samples.begin()) return samples.front().pose;
  if (after == samples.end()) return samples.back().pose;
  const OdometrySample& a = *(after - 1);
  const OdometrySample& b = *after;
  const double span = b.stamp_s - a.stamp_s;
  const double w = span > 0.0 ? (t - a.stamp_s) / span : 0.0;
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(a.pose.linear()).slerp(w, Eigen::Quaterniond(b.pose.linear())).toRotationMatrix();
  T.translation() = (1.0 - w) * a.pose.translation() + w * b.pose.translation();
  return T;
}

}  // namespace artemis::datasets::detail
