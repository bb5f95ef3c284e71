#include "artemis/eval/box_truth.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace artemis::eval {

namespace {

void checkParams(const TruthBox& box, const BoxTruthParams& params) {
  if (!box.size_m.allFinite() || !(box.size_m.minCoeff() >= 0.0) || !(params.shell_m >= 0.0) ||
      !(params.bottom_ignore_m >= 0.0)) {
    throw std::invalid_argument(
        fmt::format("boxRegion: box size ({}, {}, {}) m, shell {} m, bottom {} m: expected finite values >= 0",
                    box.size_m.x(), box.size_m.y(), box.size_m.z(), params.shell_m, params.bottom_ignore_m));
  }
}

// p_B in the box frame (origin at the bottom face's centre, z up).
BoxRegion regionInBox(const Eigen::Vector3d& size_m, const Eigen::Vector3d& p_B, const BoxTruthParams& params) {
  const double dx = std::abs(p_B.x()) - 0.5 * size_m.x();
  const double dy = std::abs(p_B.y()) - 0.5 * size_m.y();
  const double z = p_B.z();
  if (dx <= 0.0 && dy <= 0.0 && z >= 0.0 && z <= size_m.z()) {
    return z < params.bottom_ignore_m ? BoxRegion::kBottom : BoxRegion::kInside;
  }
  const double s = params.shell_m;
  if (dx <= s && dy <= s && z >= -s && z <= size_m.z() + s) return BoxRegion::kShell;
  return BoxRegion::kOutside;
}

}  // namespace

BoxRegion boxRegion(const TruthBox& box, const Eigen::Vector3d& p_F, const BoxTruthParams& params) {
  checkParams(box, params);
  return regionInBox(box.size_m, box.T_F_B.inverse() * p_F, params);
}

std::vector<SemanticId> boxTruth(std::span<const Eigen::Vector3f> points_F, std::span<const TruthBox> boxes,
                                 const BoxTruthParams& params) {
  std::vector<SemanticId> truth(points_F.size(), kOutsideBoxes);
  std::vector<std::uint8_t> ignored(points_F.size(), 0);
  for (std::size_t i = 0; i < points_F.size(); ++i) ignored[i] = points_F[i].allFinite() ? 0 : 1;
  for (const TruthBox& box : boxes) {
    checkParams(box, params);
    const Eigen::Isometry3d T_B_F = box.T_F_B.inverse();
    // A cheap reject first: the sphere around the grown box.
    const double reach = 0.5 * (box.size_m + Eigen::Vector3d::Constant(2.0 * params.shell_m)).norm();
    const Eigen::Vector3d centre_F = box.T_F_B * Eigen::Vector3d(0.0, 0.0, 0.5 * box.size_m.z());
    for (std::size_t i = 0; i < points_F.size(); ++i) {
      if (ignored[i] != 0) continue;
      const Eigen::Vector3d p_F = points_F[i].cast<double>();
      if ((p_F - centre_F).squaredNorm() > reach * reach) continue;
      const BoxRegion region = regionInBox(box.size_m, T_B_F * p_F, params);
      if (region == BoxRegion::kOutside) continue;
      if (region != BoxRegion::kInside || box.class_id == kNoSemanticClass ||
          (truth[i] != kOutsideBoxes && truth[i] != box.class_id)) {
        ignored[i] = 1;
      } else {
        truth[i] = box.class_id;
      }
    }
  }
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (ignored[i] != 0) truth[i] = kNoSemanticClass;
  }
  return truth;
}

double trackTravelM(std::span<const Eigen::Vector3d> centres_W) {
  double farthest = 0.0;
  for (std::size_t a = 0; a < centres_W.size(); ++a) {
    for (std::size_t b = a + 1; b < centres_W.size(); ++b) {
      farthest = std::max(farthest, (centres_W[a] - centres_W[b]).norm());
    }
  }
  return farthest;
}

}  // namespace artemis::eval
