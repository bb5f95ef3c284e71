#pragma once
// A LiDAR scan or an aggregated cloud, structure of arrays: positions, and optionally intensity,
// raw SemanticKITTI labels and per-point times, each either empty or as long as `points`.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "artemis/core/transform.hpp"

namespace artemis {

struct PointCloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<float> intensity;       // reflectance in [0, 1] for KITTI; empty if unknown
  std::vector<std::uint32_t> labels;  // SemanticKITTI raw labels (class | instance << 16); may be empty
  std::vector<float> time_s;          // when each point was seen, s after its frame's stamp; may be empty

  [[nodiscard]] std::size_t size() const { return points.size(); }
  [[nodiscard]] bool empty() const { return points.empty(); }
  void reserve(std::size_t n);
  void clear();

  // Keeps the points for which keep(i) is true, together with their attributes; order kept.
  template <typename Pred>
  std::size_t filter(Pred keep) {
    std::size_t out = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!keep(i)) continue;
      points[out] = points[i];
      if (!intensity.empty()) intensity[out] = intensity[i];
      if (!labels.empty()) labels[out] = labels[i];
      if (!time_s.empty()) time_s[out] = time_s[i];
      ++out;
    }
    const std::size_t removed = points.size() - out;
    resizeAll(out);
    return removed;
  }

  // Appends `other`'s points transformed by T_this_other. Attributes present in both are kept
  // (times as they are: both clouds' times must count from the same stamp).
  void append(const PointCloud& other, const Isometry3d& T_this_other);

  // True when every attribute array is empty or as long as `points`.
  [[nodiscard]] bool consistent() const;

 private:
  void resizeAll(std::size_t n);
};

}  // namespace artemis
