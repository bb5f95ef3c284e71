#include "artemis/core/point_cloud.hpp"

namespace artemis {

void PointCloud::reserve(std::size_t n) {
  points.reserve(n);
  intensity.reserve(n);
  labels.reserve(n);
  time_s.reserve(n);
}

void PointCloud::clear() {
  points.clear();
  intensity.clear();
  labels.clear();
  time_s.clear();
}

void PointCloud::resizeAll(std::size_t n) {
  points.resize(n);
  if (!intensity.empty()) intensity.resize(n);
  if (!labels.empty()) labels.resize(n);
  if (!time_s.empty()) time_s.resize(n);
}

bool PointCloud::consistent() const {
  const auto fits = [&](std::size_t n) { return n == 0 || n == points.size(); };
  return fits(intensity.size()) && fits(labels.size()) && fits(time_s.size());
}

void PointCloud::append(const PointCloud& other, const Isometry3d& T_this_other) {
  if (other.empty()) return;  // nothing to add, and no attribute it lacks to drop
  const bool was_empty = points.empty();
  const bool keep_intensity = (was_empty || !intensity.empty()) && !other.intensity.empty();
  const bool keep_labels = (was_empty || !labels.empty()) && !other.labels.empty();
  const bool keep_times = (was_empty || !time_s.empty()) && !other.time_s.empty();
  if (!keep_intensity) intensity.clear();
  if (!keep_labels) labels.clear();
  if (!keep_times) time_s.clear();
  const Eigen::Isometry3f T = T_this_other.cast<float>();
  points.reserve(points.size() + other.size());
  for (const auto& p : other.points) points.push_back(T * p);
  if (keep_intensity) intensity.insert(intensity.end(), other.intensity.begin(), other.intensity.end());
  if (keep_labels) labels.insert(labels.end(), other.labels.begin(), other.labels.end());
  if (keep_times) time_s.insert(time_s.end(), other.time_s.begin(), other.time_s.end());
}

}  // namespace artemis
