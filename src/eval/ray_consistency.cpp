#include "artemis/eval/ray_consistency.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "artemis/render/ray_caster.hpp"

namespace artemis::eval {

double RayCounts::share(RayClass kind) const {
  const std::size_t n = total();
  if (n == 0) return 0.0;
  const std::size_t k = kind == RayClass::kSurface ? surface : kind == RayClass::kBlocked ? blocked : hole;
  return static_cast<double>(k) / static_cast<double>(n);
}

void RayCounts::add(RayClass kind) {
  switch (kind) {
    case RayClass::kSurface: ++surface; break;
    case RayClass::kBlocked: ++blocked; break;
    case RayClass::kHole: ++hole; break;
  }
}

RayCounts& RayCounts::operator+=(const RayCounts& other) {
  surface += other.surface;
  blocked += other.blocked;
  hole += other.hole;
  return *this;
}

std::array<std::size_t, 4> BlockedBreakdown::gapHistogram() const {
  std::array<std::size_t, 4> bins{};
  for (const float gap : gaps_m) {
    const auto bin = std::upper_bound(kGapEdges_m.begin(), kGapEdges_m.end(), gap) - kGapEdges_m.begin();
    ++bins[static_cast<std::size_t>(bin)];
  }
  return bins;
}

double BlockedBreakdown::medianGap_m() const {
  if (gaps_m.empty()) return 0.0;
  std::vector<float> sorted = gaps_m;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  if (n % 2 == 1) return sorted[n / 2];
  return 0.5 * (static_cast<double>(sorted[n / 2 - 1]) + static_cast<double>(sorted[n / 2]));
}

void RayTally::add(const RayVerdict& verdict) {
  all.add(verdict.kind);
  if (verdict.ground) ground.add(verdict.kind);
  if (verdict.kind == RayClass::kHole && !std::isfinite(verdict.hit_m)) ++hole_no_hit;
  if (verdict.kind != RayClass::kBlocked) return;
  blocked.ground += verdict.ground ? 1 : 0;
  blocked.horizontal_face += verdict.horizontal_face ? 1 : 0;
  blocked.gaps_m.push_back(verdict.range_m - verdict.hit_m);
}

RayTally& RayTally::operator+=(const RayTally& other) {
  all += other.all;
  ground += other.ground;
  hole_no_hit += other.hole_no_hit;
  blocked.ground += other.blocked.ground;
  blocked.horizontal_face += other.blocked.horizontal_face;
  blocked.gaps_m.insert(blocked.gaps_m.end(), other.blocked.gaps_m.begin(), other.blocked.gaps_m.end());
  return *this;
}

RayConsistency::RayConsistency(const MeshArrays& mesh, RayConsistencyParams params) : params_(params) {
  if (!(params_.tolerance_m > 0.0)) {
    throw std::invalid_argument(fmt::format("ray consistency: tolerance_m must be > 0, got {}", params_.tolerance_m));
  }
  if (!(params_.tolerance_share >= 0.0)) {
    throw std::invalid_argument(
        fmt::format("ray consistency: tolerance_share must be >= 0, got {}", params_.tolerance_share));
  }
  caster_ = std::make_unique<render::RayCaster>(render::MeshArrays{mesh.vertices, mesh.triangles, {}});
}

RayConsistency::~RayConsistency() = default;

RayVerdict RayConsistency::classify(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& return_W) const {
  RayVerdict v;
  if (!origin_W.allFinite() || !return_W.allFinite()) return v;
  const Eigen::Vector3f offset = return_W - origin_W;
  v.range_m = offset.norm();
  if (!(v.range_m > 0.0F)) return v;
  v.ground = static_cast<double>(return_W.z() - origin_W.z()) < -params_.ground_drop_m;
  const render::RayHit hit = caster_->intersect(origin_W, offset / v.range_m);
  if (!hit.valid()) return v;
  v.hit_m = hit.t;
  v.horizontal_face = std::abs(hit.normal_W.z()) > std::sqrt(0.5F);
  const Eigen::Vector3f hit_W = origin_W + hit.t * (offset / v.range_m);
  // The return's distance from the hit face's plane; a zero-area face (zero normal) is never hit.
  const double off_plane_m = std::abs(static_cast<double>(hit.normal_W.dot(return_W - hit_W)));
  const double tolerance_m = std::max(params_.tolerance_m, params_.tolerance_share * static_cast<double>(v.range_m));
  if (off_plane_m <= tolerance_m) {
    v.kind = RayClass::kSurface;
  } else if (hit.t < v.range_m) {
    v.kind = RayClass::kBlocked;
  }
  return v;
}

RayTally RayConsistency::classifyFrame(const Eigen::Vector3f& origin_W, std::span<const Eigen::Vector3f> returns_W) const {
  std::vector<RayVerdict> verdicts(returns_W.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, returns_W.size(), 512),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) verdicts[i] = classify(origin_W, returns_W[i]);
                    });
  RayTally tally;
  for (const RayVerdict& v : verdicts) tally.add(v);
  return tally;
}

std::vector<std::size_t> evenSubsample(std::size_t n, std::size_t count) {
  std::vector<std::size_t> out;
  if (n <= count) {
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = i;
    return out;
  }
  out.reserve(count);
  // (2k + 1) n / (2 count) < n, and strictly increasing because n > count.
  for (std::size_t k = 0; k < count; ++k) out.push_back(((2 * k + 1) * n) / (2 * count));
  return out;
}

}  // namespace artemis::eval
