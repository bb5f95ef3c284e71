#include "artemis/mapping/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "range_image.hpp"

// FreeSpaceCarver's tests of whether a scan's rays passed through a map point (see free_space.hpp).

namespace artemis::mapping {

namespace {

// A ray passes under a roof point when it passes at least this far below it.
constexpr float kUnderM = 0.02f;
// A grazing ray says nothing of the points within this distance (plus its `lateral`) of the surface
// it skims: a wall's bumps, a kerb beside the road it skims.
constexpr float kSkimBandM = 0.25f;
// A far point is seen past when every return within this angle of its direction (about the
// HDL-64E's azimuth step and half its beam spacing) ends `margin` beyond it, and there are at
// least kPastRays of them.
constexpr float kPastAngleRad = 0.25f * std::numbers::pi_v<float> / 180.0f;
const float kPastCos = std::cos(kPastAngleRad);
constexpr int kPastRays = 2;

}  // namespace

bool FreeSpaceCarver::seenFromFar(const Sweep& sweep, const Eigen::Vector3f& p_L, const Eigen::Vector3f& n_W) const {
  // Where the rays lie tens of centimetres apart, a ray passing beside p says little: the scattered
  // far points of foliage would go by the rays beside them. A ray that crosses the plane of p's
  // voxel does, where the plane stands upright (rays from the sensor meet a level plane there at
  // grazing incidence); so does a look past p along every ray near its direction.
  const bool upright = n_W != Eigen::Vector3f::Zero() && std::abs(n_W.z()) <= kLevelNormalZ;
  if (upright &&
      seenThrough(*sweep.image, p_L, sweep.R_L_W * n_W, sweep.R_L_W.col(2), Lie::kUpright, /*crossing_only=*/true)) {
    return true;
  }
  return seenPast(*sweep.image, p_L);
}

bool FreeSpaceCarver::seenPast(const detail::RangeImage& image, const Eigen::Vector3f& p_L) const {
  const float r = p_L.norm();
  const Eigen::Vector3f d = p_L / r;
  const float beyond = r + static_cast<float>(params_.margin_m + params_.margin_per_m * r);
  const detail::RangeImage::Cell cell = image.cellOf(d);
  if (image.farthestNear(cell) <= beyond) return false;
  int rays = 0;
  bool short_ray = false;
  image.forEachNear(cell, [&](const detail::RangeImage::Return& q) {
    if (q.direction.dot(d) < kPastCos) return;
    short_ray = short_ray || q.range_m <= beyond;
    ++rays;
  });
  return !short_ray && rays >= kPastRays;
}

bool FreeSpaceCarver::seenThrough(const detail::RangeImage& image, const Eigen::Vector3f& p_L,
                                  const Eigen::Vector3f& n_L, const Eigen::Vector3f& up_L, Lie lie,
                                  bool crossing_only) const {
  const float r = p_L.norm();
  const Eigen::Vector3f d = p_L / r;
  const auto lateral = static_cast<float>(params_.lateral_m + params_.lateral_per_m * r);
  const float lateral2 = lateral * lateral;
  const auto margin = static_cast<float>(params_.margin_m + params_.margin_per_m * r);
  const auto beside = static_cast<float>(params_.beside_margin_m + params_.margin_per_m * r);
  const auto min_cos = static_cast<float>(params_.min_incidence_cos);
  const bool plane = n_L != Eigen::Vector3f::Zero();
  // On level ground (and where asked) only a ray that crosses p's plane at min_cos or steeper
  // counts. The rays looked at below lie within nearAngle() of the direction to p, so their
  // incidence differs from its by less than that: where p's own is grazing, none can count. Most
  // points tested on a street are road at grazing incidence.
  if ((crossing_only || lie == Lie::kGround) && !(plane && std::abs(n_L.dot(d)) + image.nearAngle() >= min_cos)) {
    return false;
  }
  // Most points lie where this scan's rays end, or behind them: one look says no ray goes beyond.
  const detail::RangeImage::Cell cell = image.cellOf(d);
  if (image.farthestNear(cell) <= r + std::min(margin, beside) - lateral) return false;
  bool through = false;
  image.forEachNear(cell, [&](const detail::RangeImage::Return& q) {
    // The crossing lies within `lateral` of p, so a ray ending before r + margin - lateral cannot
    // end `margin` beyond it.
    if (through || q.range_m <= r + std::min(margin, beside) - lateral) return;
    const float cos_incidence = plane ? n_L.dot(q.direction) : 0.0f;
    if (std::abs(cos_incidence) >= min_cos) {
      const float t = n_L.dot(p_L) / cos_incidence;  // where the ray crosses p's surface
      through = t > 0.0f && q.range_m > t + margin && (q.direction * t - p_L).squaredNorm() <= lateral2;
      return;
    }
    if (crossing_only) return;
    // No plane, or one the ray grazes: the ray passes beside p. It counts when it comes as near as
    // `lateral` and ends well behind, unless p lies on level ground, where a ray skimming the road
    // to a car behind says nothing about the road.
    if (lie == Lie::kGround) return;
    // A ray that skims a surface to its end (a wall it runs along, the road far ahead) says nothing
    // of the points on that surface. It does pass through what stands off it, a roof or a scattered
    // remnant above the road; not through an upright surface it runs along (a parked car's side,
    // past which it reaches the road). Where the skimmed surface is unknown, nothing.
    if (image.grazing(q)) {
      if (lie == Lie::kUpright) return;
      const Eigen::Vector3f n_q = image.skimmedNormal(q);
      if (n_q == Eigen::Vector3f::Zero() || std::abs(n_q.dot(p_L - q.direction * q.range_m)) <= kSkimBandM + lateral) {
        return;
      }
    }
    const float t = q.direction.dot(p_L);  // nearest approach
    if (!(t > 0.0f) || q.range_m <= t + beside || (p_L - q.direction * t).squaredNorm() > lateral2) return;
    // A roof is seen through only from below: a ray that passes just over a parked car's roof and
    // on to the road beyond says nothing of it; one that passes under where a roof was does.
    if (lie == Lie::kRoof && (q.direction * t - p_L).dot(up_L) > -kUnderM) return;
    // A ray that passes above p on its way down would, had p been on level ground, have met that
    // ground soon after: it must end beyond, or p might be the floor it skimmed.
    const float descent = q.direction.dot(up_L);
    through = !(descent < 0.0f) || q.range_m > p_L.dot(up_L) / descent + margin;
  });
  return through;
}

}  // namespace artemis::mapping
