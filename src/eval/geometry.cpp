// evaluateGeometry: the geometry protocol of DESIGN.md ("How results are measured").
//
// Decisions the protocol leaves open:
// - The mesh samples are cropped to the reference's bounding box padded by crop_padding_m before
//   they are downsampled (cheaper; a centroid differs only for voxels cut by the box). Samples
//   outside that box are > crop_padding_m from every reference point, so they cannot count for
//   recall when tau <= crop_padding_m; for a larger tau the recall side keeps samples out to tau.
// - "Within tau" means distance <= tau, measured between downsampled points.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "artemis/eval/geometry.hpp"
#include "point_index.hpp"
#include "surface_sampling.hpp"
#include "voxel_centroids.hpp"

namespace artemis::eval {

namespace {

using detail::PointIndex;
using Points = std::vector<Eigen::Vector3f>;

// A fixed offset so that the reference's samples differ from the mesh's for the same seed.
constexpr std::uint64_t kReferenceSeedOffset = 0x9E3779B97F4A7C15ULL;

struct Box {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f max = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());

  [[nodiscard]] Box padded(double pad_m) const {
    const auto pad = static_cast<float>(pad_m);
    return {min.array() - pad, max.array() + pad};
  }
  [[nodiscard]] bool contains(const Eigen::Vector3f& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

Box boundingBox(const Points& points) {
  Box box;
  for (const auto& p : points) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

Points keepIf(const Points& points, const std::vector<std::uint8_t>& keep) {
  Points out;
  out.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (keep[i] != 0) out.push_back(points[i]);
  }
  return out;
}

std::size_t countHits(const std::vector<std::uint8_t>& hit) {
  return static_cast<std::size_t>(std::count(hit.begin(), hit.end(), std::uint8_t{1}));
}

// Forwards progress to the caller's callback, when there is one.
class StageReporter {
 public:
  explicit StageReporter(const Progress& progress) : progress_(progress) {}

  // A callback for chunkedFor-style loops over `total` items.
  [[nodiscard]] detail::ReportDone stage(std::string name, std::size_t total) const {
    if (!progress_) return {};
    progress_(name, 0, total);
    return [this, name = std::move(name), total](std::size_t done) { progress_(name, done, total); };
  }
  [[nodiscard]] std::function<void(std::size_t, std::size_t)> sampling(std::string name) const {
    if (!progress_) return {};
    return [this, name = std::move(name)](std::size_t done, std::size_t total) { progress_(name, done, total); };
  }

 private:
  const Progress& progress_;
};

// The reference as points: a mesh sampled like the evaluated one, a cloud as it is (finite
// points only); `seen` is the part of it the sensor saw (all of it without a seen cloud). Recall
// is measured over the seen part; precision over all of it, since a mesh sample on a true surface
// is right whether or not the crop kept the reference samples around it.
struct ReferenceSets {
  Points all;
  Points seen;
};

Result<ReferenceSets> referencePoints(const Reference& reference, const GeometryParams& params,
                                      const StageReporter& reporter) {
  Points points;
  Points normals;
  if (!reference.geometry.triangles.empty()) {
    if (const std::string bad = detail::checkTriangleIndices(reference.geometry); !bad.empty()) {
      return invalidArgument("reference mesh: " + bad);
    }
    points = detail::sampleSurface(reference.geometry, params.samples_per_m2, params.min_samples,
                                   params.seed + kReferenceSeedOffset, reporter.sampling("sampling the reference"),
                                   &normals);
    if (points.empty()) return invalidArgument("reference mesh has no triangle with area");
  } else {
    points.reserve(reference.geometry.vertices.size());
    for (const auto& p : reference.geometry.vertices) {
      if (p.allFinite()) points.push_back(p);
    }
    if (points.empty()) return invalidArgument("reference has no finite point");
  }
  if (reference.seen.empty()) return ReferenceSets{points, points};

  Points seen;
  seen.reserve(reference.seen.size());
  for (const auto& p : reference.seen) {
    if (p.allFinite()) seen.push_back(p);
  }
  const auto report = reporter.stage("cropping to the seen cloud", points.size());
  const PointIndex seen_index(seen);
  const auto near_seen = normals.empty() ? seen_index.within(points, reference.seen_radius_m, report)
                                         : seen_index.withinOnPlane(points, normals, reference.seen_radius_m,
                                                                    reference.seen_plane_tolerance_m, report);
  Points seen_part = keepIf(points, near_seen);
  if (seen_part.empty()) {
    return invalidArgument(
        fmt::format("no reference point lies within {} m of the seen cloud", reference.seen_radius_m));
  }
  return ReferenceSets{std::move(points), std::move(seen_part)};
}

GeometryScore scoreAtTau(double tau_m, const Points& mesh_samples, const ReferenceSets& reference, const Box& crop,
                         const StageReporter& reporter) {
  const std::string at = fmt::format("at {:.2f} m", tau_m);
  // DESIGN.md: mesh samples and reference voxel-downsampled at tau / 2.
  const std::size_t work = reference.all.size() + reference.seen.size() + mesh_samples.size();
  const auto downsampled = reporter.stage("downsampling " + at, work);
  const Points reference_ds = detail::voxelCentroids(reference.seen, 0.5 * tau_m);
  const bool cropped = reference.all.size() != reference.seen.size();
  const Points all_ds = cropped ? detail::voxelCentroids(reference.all, 0.5 * tau_m) : Points{};
  if (downsampled) downsampled(reference.all.size() + reference.seen.size());
  const Points mesh_ds = detail::voxelCentroids(mesh_samples, 0.5 * tau_m);
  if (downsampled) downsampled(work);

  GeometryScore score;
  score.tau_m = tau_m;
  score.reference_points = reference_ds.size();

  // Every downsampled sample is tested against the reference; precision counts those in the crop.
  const auto precision_report = reporter.stage("precision " + at, mesh_ds.size());
  const PointIndex reference_index(cropped ? all_ds : reference_ds);
  const auto near_reference = reference_index.within(mesh_ds, tau_m, precision_report);
  std::size_t in_crop = 0;
  std::size_t in_crop_near = 0;
  for (std::size_t i = 0; i < mesh_ds.size(); ++i) {
    if (!crop.contains(mesh_ds[i])) continue;
    ++in_crop;
    in_crop_near += near_reference[i];
  }
  score.mesh_points = in_crop;
  score.precision = in_crop > 0 ? static_cast<double>(in_crop_near) / static_cast<double>(in_crop) : 0.0;

  // A reference point has a sample within tau exactly when that sample has the reference point
  // within tau: only samples within tau of the recall reference can serve recall, so the recall
  // tree holds those alone.
  const auto recall_report = reporter.stage("recall " + at, reference_ds.size());
  // With a cropped reference the seen points are downsampled on their own and their centroids
  // differ from those of the whole reference, so the pre-filter is redone against them.
  const Points mesh_near =
      cropped ? keepIf(mesh_ds, PointIndex(reference_ds).within(mesh_ds, tau_m)) : keepIf(mesh_ds, near_reference);
  const PointIndex mesh_index(mesh_near);
  const auto near_mesh = mesh_index.within(reference_ds, tau_m, recall_report);
  score.recall = static_cast<double>(countHits(near_mesh)) / static_cast<double>(reference_ds.size());
  const double sum = score.precision + score.recall;
  score.f1 = sum > 0.0 ? 2.0 * score.precision * score.recall / sum : 0.0;
  return score;
}

}  // namespace

Status validate(const GeometryParams& params) {
  if (params.taus_m.empty()) return invalidArgument("no tau given");
  for (const double tau : params.taus_m) {
    if (!(tau > 0.0) || !std::isfinite(tau)) return invalidArgument(fmt::format("tau must be > 0 m, got {}", tau));
  }
  if (!(params.samples_per_m2 > 0.0) || !std::isfinite(params.samples_per_m2)) {
    return invalidArgument(fmt::format("samples_per_m2 must be > 0, got {}", params.samples_per_m2));
  }
  if (!(params.crop_padding_m >= 0.0) || !std::isfinite(params.crop_padding_m)) {
    return invalidArgument(fmt::format("crop_padding_m must be >= 0, got {}", params.crop_padding_m));
  }
  return Status::ok();
}

Result<std::vector<GeometryScore>> evaluateGeometry(const MeshArrays& mesh, const Reference& reference,
                                                    const GeometryParams& params, const Progress& progress) {
  if (Status s = validate(params); !s.isOk()) return s;
  if (mesh.vertices.empty() || mesh.triangles.empty()) return invalidArgument("mesh has no triangles");
  if (const std::string bad = detail::checkTriangleIndices(mesh); !bad.empty()) return invalidArgument("mesh: " + bad);
  if (reference.geometry.vertices.empty()) return invalidArgument("reference is empty");
  if (!reference.seen.empty() && (!(reference.seen_radius_m > 0.0) || !std::isfinite(reference.seen_radius_m))) {
    return invalidArgument(fmt::format("seen_radius_m must be > 0, got {}", reference.seen_radius_m));
  }

  const StageReporter reporter(progress);
  Points samples;
  ReferenceSets reference_points;
  try {  // sampleSurface throws for a sample count beyond its limit
    samples = detail::sampleSurface(mesh, params.samples_per_m2, params.min_samples, params.seed,
                                    reporter.sampling("sampling the mesh"));
    if (samples.empty()) return invalidArgument("mesh has no triangle with area");
    auto ref = referencePoints(reference, params, reporter);
    if (!ref) return ref.status();
    reference_points = std::move(*ref);
  } catch (const std::invalid_argument& e) {
    return invalidArgument(e.what());
  }

  // Precision counts samples in the padded reference box; recall may use samples out to tau.
  const Box reference_box = boundingBox(reference_points.seen);
  const Box crop = reference_box.padded(params.crop_padding_m);
  const double max_tau = *std::max_element(params.taus_m.begin(), params.taus_m.end());
  const Box keep_box = reference_box.padded(std::max(params.crop_padding_m, max_tau));
  std::vector<std::uint8_t> keep(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) keep[i] = keep_box.contains(samples[i]) ? 1 : 0;
  samples = keepIf(samples, keep);
  if (reference_points.all.size() != reference_points.seen.size()) {  // only the part near the crop matters
    std::vector<std::uint8_t> near(reference_points.all.size());
    for (std::size_t i = 0; i < near.size(); ++i)
      near[i] = keep_box.padded(max_tau).contains(reference_points.all[i]) ? 1 : 0;
    reference_points.all = keepIf(reference_points.all, near);
  }

  std::vector<GeometryScore> scores;
  for (const double tau : params.taus_m) scores.push_back(scoreAtTau(tau, samples, reference_points, crop, reporter));
  return scores;
}

}  // namespace artemis::eval
