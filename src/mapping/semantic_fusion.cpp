#include "artemis/mapping/semantic_fusion.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "artemis/core/timer.hpp"
#include "artemis/mapping/dense_evidence.hpp"
#include "artemis/mapping/frame_ground.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis::mapping {

SemanticFusion::SemanticFusion(const SemanticFusionParams& params)
    : params_(params), silhouettes_(params.geometry.silhouettes) {
  if (!(params.sigma_depth_m > 0.0) || params.depth_window_px < 0 || params.depth_window_px > 32 ||
      !(params.background_score >= 0.0 && params.background_score <= 1.0) || !(params.confidence_lambda > 0.0) ||
      !(params.voxel_prior > 0.0)) {
    throw std::invalid_argument(
        "semantic fusion: sigma_depth_m, confidence_lambda and voxel_prior must be > 0, depth_window_px in 0..32 "
        "and background_score in [0, 1] (got " +
        std::to_string(params.sigma_depth_m) + ", " + std::to_string(params.confidence_lambda) + ", " +
        std::to_string(params.depth_window_px) + ", " + std::to_string(params.background_score) + ")");
  }
}

float SemanticFusion::depthGap(const DepthProjection::Point& q, int w, int h) const {
  const int u = static_cast<int>(q.pixel % static_cast<std::uint32_t>(w));
  const int v = static_cast<int>(q.pixel / static_cast<std::uint32_t>(w));
  const std::vector<float>& depth = projected_.nearest.data();
  const int r = params_.depth_window_px;
  float nearest = std::numeric_limits<float>::infinity();
  for (int y = std::max(0, v - r); y <= std::min(h - 1, v + r); ++y) {
    const float* row = &depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(w)];
    for (int x = std::max(0, u - r); x <= std::min(w - 1, u + r); ++x) nearest = std::min(nearest, row[x]);
  }
  return q.depth - nearest;  // >= 0: the point itself is in the window
}

void SemanticFusion::buildSilhouettes(const PointCloud& points_L, const Isometry3d& T_W_L, const FrameGround& ground,
                                      const ObjectSilhouettes::LabelOf& label_of, int w, int h) {
  const Eigen::Matrix3f R_W_L = T_W_L.linear().cast<float>();
  const Eigen::Vector3f t_W_L = T_W_L.translation().cast<float>();
  silhouettes_.build(projected_.points, w, h, label_of,
                     [&](std::uint32_t i) { return ground.heightAbove(R_W_L * points_L.points[i] + t_W_L); });
}

FusionStats SemanticFusion::fuseDense(const VertexOf& vertex_of, const PointCloud& points_L, const Isometry3d& T_W_L,
                                      const CameraView& view, const semantics::SemanticObservation& observation,
                                      SemanticMesh& mesh, const semantics::Vocabulary& vocabulary) {
  Stopwatch clock;
  FusionStats stats;
  const semantics::DenseProbabilities& dense = observation.dense;
  const int w = dense.width;
  const int h = dense.height;
  projectDepth(points_L, view, w, h, projected_);
  stats.points_in_image = projected_.points.size();
  const DenseEvidence evidence(dense, mesh, params_.geometry, vocabulary);
  const FrameGround ground(points_L, T_W_L);
  const Isometry3d T_W_C = T_W_L * view.T_L_C;
  const Eigen::Vector3f camera_W = T_W_C.translation().cast<float>();
  const Eigen::Matrix3f R_W_L = T_W_L.linear().cast<float>();
  const Eigen::Vector3f t_W_L = T_W_L.translation().cast<float>();
  const ObjectSilhouettes::LabelOf label_of = objectLabels(observation, vocabulary);
  buildSilhouettes(points_L, T_W_L, ground, label_of, w, h);
  const auto inv_sigma_d = static_cast<float>(1.0 / params_.sigma_depth_m);
  // Each point's vertex, weight and distribution in parallel; then added in scan order, as fuse()
  // does, so that points sharing a cell add up in a fixed order whatever the thread count.
  const std::size_t n = projected_.points.size();
  const std::size_t slots = evidence.slots();
  std::vector<std::uint32_t> vertex(n, VoxelMap::kNoVertex);
  std::vector<float> omega(n, 0.0f);
  std::vector<float> distribution(n * slots);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<float> scratch(2 * evidence.channels());
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const DepthProjection::Point& q = projected_.points[k];
      vertex[k] = vertex_of(q.index);
      if (vertex[k] == VoxelMap::kNoVertex) continue;
      const Eigen::Vector3f p_W = R_W_L * points_L.points[q.index] + t_W_L;
      const int u = static_cast<int>(q.pixel % static_cast<std::uint32_t>(w));
      const int v = static_cast<int>(q.pixel / static_cast<std::uint32_t>(w));
      if (silhouettes_.behind(u, v, q.depth, label_of(u, v))) continue;
      // Height only: a vertex's normal is the sensor direction until its voxel is meshed.
      const float sigma_mask =
          evidence.read(u, v, ground.heightAbove(p_W), nullptr, &distribution[k * slots], scratch.data());
      const float cos_view = std::abs((p_W - camera_W).normalized().dot(mesh.normals()[vertex[k]]));
      omega[k] = sigma_mask * cos_view * std::exp(-depthGap(q, w, h) * inv_sigma_d);  // eq. 1
    }
  });
  for (std::size_t k = 0; k < n; ++k) {
    if (vertex[k] == VoxelMap::kNoVertex || !(omega[k] > 0.0f)) continue;
    mesh.observeDistribution(vertex[k], &distribution[k * slots], omega[k]);
    ++stats.observations;
  }
  stats.ms = clock.elapsedMs();
  return stats;
}

FusionStats SemanticFusion::fuse(const PointCloud& points_L, const VoxelMap& map, const Isometry3d& T_W_L,
                                 const CameraView& view, const semantics::SemanticObservation& observation,
                                 SemanticMesh& mesh, const semantics::Vocabulary* vocabulary) {
  return fuseWith([&map](std::size_t i) { return map.insertedVertex(i); }, points_L, T_W_L, view, observation, mesh,
                  vocabulary);
}

FusionStats SemanticFusion::fuseLate(const PointCloud& points_L, const VoxelMap& map, const Isometry3d& T_W_L,
                                     const CameraView& view, const semantics::SemanticObservation& observation,
                                     SemanticMesh& mesh, const semantics::Vocabulary* vocabulary) {
  const Eigen::Matrix3f R = T_W_L.linear().cast<float>();
  const Eigen::Vector3f t = T_W_L.translation().cast<float>();
  return fuseWith([&](std::size_t i) { return map.vertexAt(R * points_L.points[i] + t); }, points_L, T_W_L, view,
                  observation, mesh, vocabulary);
}

FusionStats SemanticFusion::fuseWith(const VertexOf& vertex_of, const PointCloud& points_L, const Isometry3d& T_W_L,
                                     const CameraView& view, const semantics::SemanticObservation& observation,
                                     SemanticMesh& mesh, const semantics::Vocabulary* vocabulary) {
  if (observation.observed && observation.isDense()) {
    return fuseDense(vertex_of, points_L, T_W_L, view, observation, mesh,
                     vocabulary != nullptr ? *vocabulary : semantics::Vocabulary::semanticKitti());
  }
  Stopwatch clock;
  FusionStats stats;
  if (!observation.observed || observation.mask_ids.empty()) return stats;
  const int w = observation.mask_ids.width();
  const int h = observation.mask_ids.height();
  // Each point's pixel and depth, and the nearest LiDAR depth per pixel.
  projectDepth(points_L, view, w, h, projected_);
  stats.points_in_image = projected_.points.size();
  const ObjectSilhouettes::LabelOf label_of =
      objectLabels(observation, vocabulary != nullptr ? *vocabulary : semantics::Vocabulary::semanticKitti());
  if (silhouettes_.enabled()) buildSilhouettes(points_L, T_W_L, FrameGround(points_L, T_W_L), label_of, w, h);

  // Slot of each mask's class, and of the background.
  std::vector<int> mask_slot(observation.masks.size() + 1, 0);
  for (std::size_t m = 0; m < observation.masks.size(); ++m) {
    const int s = mesh.slotOf(observation.masks[m].class_id);
    if (s < 0) throw std::logic_error("semantic fusion: a mask's class has no slot in the mesh");
    mask_slot[m + 1] = s;
  }

  const Isometry3d T_W_C = T_W_L * view.T_L_C;
  const Eigen::Vector3f camera_W = T_W_C.translation().cast<float>();
  const Eigen::Matrix3f R_W_L = T_W_L.linear().cast<float>();
  const Eigen::Vector3f t_W_L = T_W_L.translation().cast<float>();
  const auto inv_sigma_d = static_cast<float>(1.0 / params_.sigma_depth_m);
  const auto background = static_cast<float>(params_.background_score);
  // In scan order, one point after the other: points sharing a cell add up in a fixed order.
  for (const DepthProjection::Point& q : projected_.points) {
    const std::uint32_t vertex = vertex_of(q.index);
    if (vertex == VoxelMap::kNoVertex) continue;  // a point the map refused
    const int u = static_cast<int>(q.pixel % static_cast<std::uint32_t>(w));
    const int v = static_cast<int>(q.pixel / static_cast<std::uint32_t>(w));
    const float d_depth = depthGap(q, w, h);
    const std::uint16_t id = observation.mask_ids.at(u, v);
    if (silhouettes_.behind(u, v, q.depth, label_of(u, v))) continue;
    const float score = id == 0 ? background : observation.masks[id - 1].score;
    const Eigen::Vector3f p_W = R_W_L * points_L.points[q.index] + t_W_L;
    const Eigen::Vector3f ray = (p_W - camera_W).normalized();
    const float cos_view = std::abs(ray.dot(mesh.normals()[vertex]));
    const float omega = score * cos_view * std::exp(-d_depth * inv_sigma_d);
    if (!(omega > 0.0f)) continue;
    mesh.observe(vertex, static_cast<std::size_t>(mask_slot[id]), omega);
    ++stats.observations;
  }
  stats.ms = clock.elapsedMs();
  return stats;
}

}  // namespace artemis::mapping
