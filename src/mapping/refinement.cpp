#include "artemis/mapping/refinement.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "artemis/core/projection.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/mapping/frame_ground.hpp"
#include "artemis/render/rasterizer.hpp"
#include "semantic_update.hpp"
#include "view_candidates.hpp"

namespace artemis::mapping {

namespace {

// A vertex is seen through when the nearest LiDAR return around its pixel lies this much farther.
constexpr float kSeenThroughM = 0.5f;
constexpr float kSeenThroughShare = 0.05f;

using detail::Candidate;
using detail::fuseColours;
using detail::gatherCandidates;
using detail::luminance;
using detail::ViewSampler;
using detail::weigh;

// The faces of `voxels`, voxel after voxel. Looked up (a hash probe each) and copied side by side.
std::vector<Face> facesOf(const VoxelMap& map, const SemanticMesh& mesh, const std::vector<std::uint32_t>& voxels) {
  std::vector<const std::vector<Face>*> lists(voxels.size());
  std::vector<std::size_t> offsets(voxels.size() + 1, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      lists[i] = mesh.voxelFaces(map.keyAt(voxels[i]));
      offsets[i + 1] = lists[i] != nullptr ? lists[i]->size() : 0;
    }
  });
  for (std::size_t i = 0; i < voxels.size(); ++i) offsets[i + 1] += offsets[i];
  std::vector<Face> faces(offsets.back());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (lists[i] != nullptr)
        std::copy(lists[i]->begin(), lists[i]->end(), faces.begin() + static_cast<std::ptrdiff_t>(offsets[i]));
    }
  });
  return faces;
}

// The vertices of `voxels`, voxel after voxel.
std::vector<std::uint32_t> verticesOf(const VoxelMap& map, const std::vector<std::uint32_t>& voxels) {
  std::vector<std::size_t> offsets(voxels.size() + 1, 0);
  for (std::size_t i = 0; i < voxels.size(); ++i) offsets[i + 1] = offsets[i] + map.voxelAt(voxels[i]).vertices.size();
  std::vector<std::uint32_t> vertices(offsets.back());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 256), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const std::vector<std::uint32_t>& own = map.voxelAt(voxels[i]).vertices;
      std::copy(own.begin(), own.end(), vertices.begin() + static_cast<std::ptrdiff_t>(offsets[i]));
    }
  });
  return vertices;
}

}  // namespace

Refinement::Refinement(const RefinementParams& params, double background_score, const GeometricPriorParams& geometry)
    : params_(params), background_score_(background_score), geometry_(geometry), silhouettes_(geometry.silhouettes) {
  if (!(params.sigma_photo > 0.0) || !(params.sigma_geom > 0.0) || !(params.depth_epsilon_m > 0.0) ||
      !(params.sigma_obs > 0.0) || !(params.min_reliability >= 0.0 && params.min_reliability <= 1.0) ||
      !(params.max_range_m > 0.0) || !(params.mask_floor > 0.0 && params.mask_floor < 1.0) ||
      !(background_score >= 0.0 && background_score <= 1.0) || !(params.stage_one_weight > 0.0) ||
      params.mask_border_px < 0) {
    throw std::invalid_argument(
        "refinement: sigma_photo, sigma_geom, depth_epsilon_m, sigma_obs and max_range_m must be > 0, "
        "min_reliability in [0, 1], mask_floor in (0, 1), background_score in [0, 1], stage_one_weight > 0 and "
        "mask_border_px >= 0");
  }
}

RefinementStats Refinement::refine(const VoxelMap& map, SemanticMesh& mesh, const RefinementInput& input,
                                   const Isometry3d& T_W_L) {
  return refine(look(map, mesh, input, T_W_L), mesh.positions(), mesh, input, T_W_L);
}

ViewLook Refinement::look(const VoxelMap& map, const SemanticMesh& mesh, const RefinementInput& input,
                          const Isometry3d& T_W_L) const {
  ViewLook look;
  if (input.view == nullptr || !input.view->hasImage() || input.view->image.channels() < 3) return look;
  const CameraView& view = *input.view;
  const bool semantic = params_.semantic_refinement && input.observation != nullptr && input.observation->observed &&
                        mesh.slotCount() >= 2;
  if (!input.texture && !semantic) return look;
  const PinholeCamera& camera = view.camera;
  const int w = view.image.width();
  const int h = view.image.height();
  if (w != camera.width_px || h != camera.height_px) {  // the dataset readers refuse such images
    throw std::invalid_argument("refinement: the image is " + std::to_string(w) + "x" + std::to_string(h) +
                                " but the camera " + std::to_string(camera.width_px) + "x" +
                                std::to_string(camera.height_px));
  }
  look.refines = true;
  look.vertex_count = mesh.vertexCount();
  // 1. Culling: blocks, then voxels.
  Stopwatch clock;
  look.voxels = voxelsInView(map, camera, T_W_L * view.T_L_C, params_.max_range_m);
  look.cull_ms = clock.elapsedMs();
  // The faces of the voxels in view (step 2 renders them) and their vertices (step 3 samples them).
  clock.reset();
  look.faces = facesOf(map, mesh, look.voxels);
  look.vertices = verticesOf(map, look.voxels);
  look.copy_ms = clock.elapsedMs();
  return look;
}

RefinementStats Refinement::refine(const ViewLook& look, std::span<const Eigen::Vector3f> positions,
                                   SemanticMesh& mesh, const RefinementInput& input, const Isometry3d& T_W_L) {
  RefinementStats stats;
  if (!look.refines) return stats;
  if (positions.size() < look.vertex_count) {
    throw std::invalid_argument("refinement: " + std::to_string(positions.size()) + " vertex positions for a look at " +
                                std::to_string(look.vertex_count) + " vertices");
  }
  const CameraView& view = *input.view;
  const semantics::SemanticObservation* observation = params_.semantic_refinement && input.observation != nullptr &&
                                                              input.observation->observed && mesh.slotCount() >= 2
                                                          ? input.observation
                                                          : nullptr;
  const bool texture = input.texture;
  const PinholeCamera& camera = view.camera;
  const int w = view.image.width();
  const int h = view.image.height();
  const Isometry3d T_W_C = T_W_L * view.T_L_C;

  // The frame's LiDAR depth, its least within the window: bridges the gaps between beams and marks
  // the pixels just beside a nearer object's silhouette. On another core, while the mesh in view is
  // rendered.
  const bool lidar = input.points_L != nullptr && params_.lidar_window_px >= 0;
  tbb::task_group lidar_depth;
  if (lidar) {
    lidar_depth.run([&] {
      projectDepth(*input.points_L, view, camera.width_px, camera.height_px, lidar_);
      minFilter(lidar_.nearest, params_.lidar_window_px);
    });
  }
  stats.voxels = look.voxels;
  const std::vector<std::uint32_t>& voxels = stats.voxels;
  stats.voxels_in_view = voxels.size();
  stats.cull_ms = look.cull_ms;

  // 2. The reference depth: the faces of the voxels in view, rendered from the camera.
  Stopwatch clock;
  const std::vector<Face>& faces = look.faces;
  stats.faces_rendered = faces.size();
  render::View render_view;
  render_view.camera = camera;
  render_view.T_W_C = T_W_C;
  render_view.far_m = params_.max_range_m * 2.0;
  render::Picture reference = render::rasterize({positions.first(look.vertex_count), faces, {}}, render_view);
  lidar_depth.wait();
  if (lidar) {
    std::vector<float>& z = reference.depth.data();
    const std::vector<float>& nearest = lidar_.nearest.data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, std::min(z.size(), nearest.size()), 16384),
                      [&](const auto& range) {
                        for (std::size_t k = range.begin(); k < range.end(); ++k) z[k] = std::min(z[k], nearest[k]);
                      });
  }
  ViewMemory* memory = texture ? input.memory : nullptr;
  if (memory != nullptr) {
    memory->depth = ImageU16(w, h, 1);
    const std::vector<float>& z = reference.depth.data();
    std::vector<std::uint16_t>& q = memory->depth.data();
    constexpr float kMaxSteps = static_cast<float>(ViewMemory::kNoDepth - 1);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, q.size(), 16384), [&](const auto& range) {
      for (std::size_t k = range.begin(); k < range.end(); ++k) {  // a surface beyond 131 m stays one, at 131 m
        q[k] =
            std::isfinite(z[k])
                ? static_cast<std::uint16_t>(std::lround(std::clamp(z[k] / ViewMemory::kDepthStepM, 0.0f, kMaxSteps)))
                : ViewMemory::kNoDepth;
      }
    });
    memory->T_W_C = T_W_C;
    memory->vertices = static_cast<std::uint32_t>(look.vertex_count);
  }
  stats.depth_ms = look.copy_ms + clock.elapsedMs();

  // 3. Each vertex of those voxels: its pixel, colour (bilinear) and geometric residual.
  clock.reset();
  const ImageF32& z_ref = reference.depth;
  std::vector<Candidate> candidates = gatherCandidates(positions, look.vertices, ViewSampler(view, T_W_C, params_),
                                                       [&z_ref](int u, int v) { return z_ref.at(u, v); });
  for (const Candidate& c : candidates) stats.vertices_in_view += c.valid ? 1 : 0;

  // 4. The exposure gain: median of observed / mapped luminance over coloured, unoccluded vertices.
  const double gain = params_.exposure_gain ? exposureGain(candidates, mesh, params_) : 1.0;
  stats.gain = gain;
  if (memory != nullptr) memory->gain = gain;

  // 5. eq. 9-10: W of every candidate, against the colour means before this view's update.
  weigh(candidates, mesh, params_, gain);

  // 6. The updates, texture and semantics side by side; every candidate is a distinct vertex.
  const auto fuse_texture = [&] { fuseColours(candidates, mesh, params_, look.vertex_count); };
  const auto refine_semantics = [&] {
    // A vertex this frame's LiDAR saw through (every return around its pixel lies well behind it)
    // was not there when the image was taken, such as the trail a moving car left: the pixel shows
    // what lies behind, so it says nothing of the vertex's class.
    const auto seen_through = [&](const Candidate& c) {
      if (!lidar) return false;
      const float d = lidar_.nearest.at(c.u, c.v);
      return std::isfinite(d) && d > c.depth_m + std::max(kSeenThroughM, kSeenThroughShare * c.depth_m);
    };
    // A vertex well behind a nearer return of the object class its pixel shows: the object's mask
    // spilling past its silhouette (ObjectSilhouettes).
    const semantics::Vocabulary& vocabulary =
        input.vocabulary != nullptr ? *input.vocabulary : semantics::Vocabulary::semanticKitti();
    const ObjectSilhouettes::LabelOf label_of = objectLabels(*observation, vocabulary);
    // The frame's ground: for the dense prior, and for the silhouettes (whose returns on it are none).
    const bool need_ground = input.points_L != nullptr && (observation->isDense() || (lidar && silhouettes_.enabled()));
    const FrameGround ground = need_ground ? FrameGround(*input.points_L, T_W_L) : FrameGround();
    const Eigen::Matrix3f R_W_L = T_W_L.linear().cast<float>();
    const Eigen::Vector3f t_W_L = T_W_L.translation().cast<float>();
    silhouettes_.build(lidar ? lidar_.points : std::vector<DepthProjection::Point>{}, camera.width_px, camera.height_px,
                       label_of,
                       [&](std::uint32_t i) { return ground.heightAbove(R_W_L * input.points_L->points[i] + t_W_L); });
    std::vector<SemanticVote> votes;
    for (const Candidate& c : candidates) {
      if (c.reliability > 0.0f && !seen_through(c) && !silhouettes_.behind(c.u, c.v, c.depth_m, label_of(c.u, c.v))) {
        votes.push_back({c.vertex, c.u, c.v, c.reliability});
      }
    }
    const MaskUpdateSettings settings{static_cast<float>(params_.mask_floor), static_cast<float>(background_score_),
                                      params_.mask_border_px};
    if (observation->isDense()) {
      updateFromDense(votes, observation->dense, geometry_,
                      input.vocabulary != nullptr ? *input.vocabulary : semantics::Vocabulary::semanticKitti(), ground,
                      settings, mesh);
    } else {
      updateFromMasks(votes, *observation, settings, mesh);
    }
  };
  if (texture && observation != nullptr) {
    tbb::parallel_invoke(fuse_texture, refine_semantics);
  } else if (texture) {
    fuse_texture();
  } else {
    refine_semantics();
  }
  for (const Candidate& c : candidates) {
    if (!(c.reliability > 0.0f)) continue;
    stats.vertices_updated += texture ? 1 : 0;
    stats.vertices_labelled += observation != nullptr ? 1 : 0;
  }
  stats.fuse_ms = clock.elapsedMs();
  return stats;
}

RefinementStats Refinement::revisit(SemanticMesh& mesh, const CameraView& view, const ViewMemory& memory,
                                    std::span<const Eigen::Vector3f> positions) {
  RefinementStats stats;
  if (memory.empty() || !view.hasImage() || view.image.channels() < 3) return stats;
  if (memory.depth.width() != view.image.width() || memory.depth.height() != view.image.height()) {
    throw std::invalid_argument("refinement: a revisited view's depth is " + std::to_string(memory.depth.width()) +
                                "x" + std::to_string(memory.depth.height()) + " but its image " +
                                std::to_string(view.image.width()) + "x" + std::to_string(view.image.height()));
  }
  const auto end = static_cast<std::uint32_t>(positions.size());
  if (memory.vertices >= end) return stats;  // nothing new

  // The vertices added since, still without colour.
  Stopwatch clock;
  const ImageU16& depth = memory.depth;
  const auto depth_at = [&depth](int u, int v) {
    const std::uint16_t q = depth.at(u, v);
    return q == ViewMemory::kNoDepth ? std::numeric_limits<float>::infinity()
                                     : static_cast<float>(q) * ViewMemory::kDepthStepM;
  };
  const ViewSampler sampler(view, memory.T_W_C, params_, static_cast<float>(params_.max_range_m));
  tbb::enumerable_thread_specific<std::vector<Candidate>> found;
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(memory.vertices, end, 4096), [&](const auto& range) {
    std::vector<Candidate>& mine = found.local();
    for (std::uint32_t v = range.begin(); v < range.end(); ++v) {
      if (mesh.hasColour(v)) continue;
      Candidate c;
      c.vertex = v;
      if (sampler.sample(positions[v], c, depth_at)) mine.push_back(c);
    }
  });
  std::vector<Candidate> candidates;
  for (const std::vector<Candidate>& mine : found) candidates.insert(candidates.end(), mine.begin(), mine.end());
  stats.vertices_in_view = candidates.size();
  stats.gain = memory.gain;
  weigh(candidates, mesh, params_, memory.gain);
  fuseColours(candidates, mesh, params_, end);
  const std::vector<std::uint32_t>& voxel_of = mesh.voxelIndices();
  for (const Candidate& c : candidates) {
    if (!(c.reliability > 0.0f)) continue;
    ++stats.vertices_updated;
    stats.voxels.push_back(voxel_of[c.vertex]);
  }
  std::sort(stats.voxels.begin(), stats.voxels.end());
  stats.voxels.erase(std::unique(stats.voxels.begin(), stats.voxels.end()), stats.voxels.end());
  stats.voxels_in_view = stats.voxels.size();
  stats.fuse_ms = clock.elapsedMs();
  return stats;
}

}  // namespace artemis::mapping
