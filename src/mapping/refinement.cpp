#include "artemis/mapping/refinement.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "artemis/core/colour.hpp"
#include "artemis/core/projection.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/mapping/frame_ground.hpp"
#include "artemis/render/rasterizer.hpp"
#include "semantic_update.hpp"

namespace artemis::mapping {

namespace {

// sRGB (8-bit) to linear RGB.
const std::array<float, 256>& srgbToLinear() {
  static const std::array<float, 256> kTable = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[static_cast<std::size_t>(i)] = static_cast<float>(srgbDecode(i / 255.0));
    return t;
  }();
  return kTable;
}

float luminance(const Eigen::Vector3f& c) {
  return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
}

// A vertex is seen through when the nearest LiDAR return around its pixel lies this much farther.
constexpr float kSeenThroughM = 0.5f;
constexpr float kSeenThroughShare = 0.05f;

struct Candidate {
  std::uint32_t vertex = 0;
  Eigen::Vector3f colour = Eigen::Vector3f::Zero();  // linear RGB, before the gain
  float r_geom = 0.0f;
  float depth_m = 0.0f;      // d_proj
  float reliability = 0.0f;  // W
  int u = 0;                 // nearest pixel
  int v = 0;
  bool valid = false;    // projects into the image
  bool sampled = false;  // its colour was read (not when r_geom alone rules it out)
};

// Where a candidate's W must fall below min_reliability whatever its colour: r_geom / sigma_geom
// above sqrt(-2 ln min_reliability), with a margin for rounding, and never below sigma_geom (the
// exposure gain reads the colours of candidates up to sigma_geom). Its colour is then not sampled.
float hiddenResidual(const RefinementParams& params) {
  if (!params.reliability || !(params.min_reliability > 0.0)) return std::numeric_limits<float>::infinity();
  const double w_bound = params.sigma_geom * std::sqrt(-2.0 * std::log(params.min_reliability));
  return static_cast<float>(std::max(w_bound, params.sigma_geom) * (1.0 + 1e-4));
}

// Step 3 for one vertex: its pixel, the colour there (bilinear, linear RGB) and r_geom against
// the reference depth (+inf: none). False when it does not project into the image.
class ViewSampler {
 public:
  // Vertices deeper than max_depth_m are left out.
  ViewSampler(const CameraView& view, const Isometry3d& T_W_C, const RefinementParams& params,
              float max_depth_m = std::numeric_limits<float>::infinity())
      : view_(view),
        project_(view.camera),
        w_(view.image.width()),
        h_(view.image.height()),
        epsilon_(static_cast<float>(params.depth_epsilon_m)),
        hidden_(hiddenResidual(params)),
        max_depth_(max_depth_m),
        lut_(srgbToLinear()) {
    const Isometry3d T_C_W = T_W_C.inverse();
    R_ = T_C_W.linear().cast<float>();
    t_ = T_C_W.translation().cast<float>();
  }

  template <typename DepthAt>
  bool sample(const Eigen::Vector3f& p_W, Candidate& c, const DepthAt& depth_at) const {
    const Eigen::Vector3f p_C = R_ * p_W + t_;
    if (!(p_C.z() > static_cast<float>(PinholeCamera::kMinDepthM)) || p_C.z() > max_depth_) return false;
    const Eigen::Vector2f uv = project_(p_C);
    const float u = uv.x();
    const float v = uv.y();
    if (!(u >= 0.0f && v >= 0.0f && u <= static_cast<float>(w_ - 1) && v <= static_cast<float>(h_ - 1))) return false;
    c.u = static_cast<int>(std::lround(u));
    c.v = static_cast<int>(std::lround(v));
    const float d_ref = depth_at(c.u, c.v);
    c.depth_m = p_C.z();
    c.r_geom = std::isfinite(d_ref) ? std::abs(p_C.z() - d_ref) / std::max(d_ref, epsilon_) : 0.0f;
    c.valid = true;
    if (c.r_geom > hidden_) return true;  // W will be 0 whatever the colour
    c.sampled = true;
    const int u0 = std::min(static_cast<int>(u), w_ - 2 < 0 ? 0 : w_ - 2);
    const int v0 = std::min(static_cast<int>(v), h_ - 2 < 0 ? 0 : h_ - 2);
    const float a = u - static_cast<float>(u0);
    const float b = v - static_cast<float>(v0);
    const int u1 = std::min(u0 + 1, w_ - 1);
    const int v1 = std::min(v0 + 1, h_ - 1);
    c.colour = (1 - a) * (1 - b) * texel(u0, v0) + a * (1 - b) * texel(u1, v0) + (1 - a) * b * texel(u0, v1) +
               a * b * texel(u1, v1);
    return true;
  }

 private:
  [[nodiscard]] Eigen::Vector3f texel(int u, int v) const {
    const ImageU8& im = view_.image;
    return {lut_[im.at(u, v, 0)], lut_[im.at(u, v, 1)], lut_[im.at(u, v, 2)]};
  }

  const CameraView& view_;
  PinholeProjector project_;
  Eigen::Matrix3f R_;
  Eigen::Vector3f t_;
  int w_;
  int h_;
  float epsilon_;
  float hidden_;
  float max_depth_;
  const std::array<float, 256>& lut_;
};

// Step 3 for every vertex of `voxels`; the candidates keep the voxels' order.
template <typename DepthAt>
std::vector<Candidate> gatherCandidates(const VoxelMap& map, const SemanticMesh& mesh,
                                        const std::vector<std::uint32_t>& voxels, const ViewSampler& sampler,
                                        const DepthAt& depth_at) {
  std::vector<std::size_t> offset(voxels.size() + 1, 0);
  for (std::size_t k = 0; k < voxels.size(); ++k) offset[k + 1] = offset[k] + map.voxelAt(voxels[k]).vertices.size();
  std::vector<Candidate> candidates(offset.back());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 64), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const Voxel& voxel = map.voxelAt(voxels[k]);
      for (std::size_t j = 0; j < voxel.vertices.size(); ++j) {
        Candidate& c = candidates[offset[k] + j];
        c.vertex = voxel.vertices[j];
        sampler.sample(mesh.positions()[c.vertex], c, depth_at);
      }
    }
  });
  return candidates;
}

// Step 5: eq. 9-10, W of every candidate against the colour means before the update (the colours
// divided by the view's gain first); below min_reliability W is 0.
void weigh(std::vector<Candidate>& candidates, const SemanticMesh& mesh, const RefinementParams& params, double gain) {
  const auto inv_gain = static_cast<float>(1.0 / gain);
  const auto inv_sp = static_cast<float>(1.0 / params.sigma_photo);
  const auto inv_sg = static_cast<float>(1.0 / params.sigma_geom);
  const auto min_w = static_cast<float>(params.min_reliability);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      Candidate& c = candidates[k];
      if (!c.sampled) {
        c.reliability = 0.0f;
        continue;
      }
      c.colour *= inv_gain;
      float reliability = 1.0f;
      if (params.reliability) {
        const float r_photo = mesh.hasColour(c.vertex) ? (c.colour - mesh.colourMean(c.vertex)).norm() : 0.0f;
        const float e = r_photo * inv_sp;
        const float g = c.r_geom * inv_sg;
        reliability = std::exp(-0.5f * (e * e + g * g));
      }
      c.reliability = reliability >= min_w && reliability > 0.0f ? reliability : 0.0f;
    }
  });
}

// The colour update: an observation with variance sigma_obs^2 / W; every candidate is a distinct vertex.
void fuseColours(const std::vector<Candidate>& candidates, SemanticMesh& mesh, const RefinementParams& params) {
  const auto obs_var = static_cast<float>(params.sigma_obs * params.sigma_obs);
  mesh.reserveColours();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const Candidate& c = candidates[k];
      if (c.reliability > 0.0f) mesh.fuseColour(c.vertex, c.colour, obs_var / c.reliability);
    }
  });
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
  RefinementStats stats;
  if (input.view == nullptr || !input.view->hasImage() || input.view->image.channels() < 3) return stats;
  const CameraView& view = *input.view;
  const semantics::SemanticObservation* observation = params_.semantic_refinement && input.observation != nullptr &&
                                                              input.observation->observed && mesh.slotCount() >= 2
                                                          ? input.observation
                                                          : nullptr;
  const bool texture = input.texture;
  if (!texture && observation == nullptr) return stats;
  const PinholeCamera& camera = view.camera;
  const int w = view.image.width();
  const int h = view.image.height();
  if (w != camera.width_px || h != camera.height_px) {  // the dataset readers refuse such images
    throw std::invalid_argument("refinement: the image is " + std::to_string(w) + "x" + std::to_string(h) +
                                " but the camera " + std::to_string(camera.width_px) + "x" +
                                std::to_string(camera.height_px));
  }
  const Isometry3d T_W_C = T_W_L * view.T_L_C;

  // 1. Culling: blocks, then voxels.
  Stopwatch clock;
  stats.voxels = voxelsInView(map, camera, T_W_C, params_.max_range_m);
  const std::vector<std::uint32_t>& voxels = stats.voxels;
  stats.voxels_in_view = voxels.size();
  stats.cull_ms = clock.elapsedMs();

  // 2. The reference depth: the faces of the voxels in view, rendered from the camera.
  clock.reset();
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (const std::uint32_t index : voxels) {
    if (const auto* f = mesh.voxelFaces(map.keyAt(index))) faces.insert(faces.end(), f->begin(), f->end());
  }
  stats.faces_rendered = faces.size();
  render::View render_view;
  render_view.camera = camera;
  render_view.T_W_C = T_W_C;
  render_view.far_m = params_.max_range_m * 2.0;
  render::Picture reference = render::rasterize({mesh.positions(), faces, {}}, render_view);
  if (input.points_L != nullptr && params_.lidar_window_px >= 0) {
    // The frame's LiDAR depth, its least within the window: bridges the gaps between beams and
    // marks the pixels just beside a nearer object's silhouette.
    projectDepth(*input.points_L, view, camera.width_px, camera.height_px, lidar_);
    minFilter(lidar_.nearest, params_.lidar_window_px);
    std::vector<float>& z = reference.depth.data();
    const std::vector<float>& lidar = lidar_.nearest.data();
    for (std::size_t k = 0; k < std::min(z.size(), lidar.size()); ++k) z[k] = std::min(z[k], lidar[k]);
  }
  ViewMemory* memory = texture ? input.memory : nullptr;
  if (memory != nullptr) {
    memory->depth = ImageU16(w, h, 1);
    const std::vector<float>& z = reference.depth.data();
    std::vector<std::uint16_t>& q = memory->depth.data();
    constexpr float kMaxSteps = static_cast<float>(ViewMemory::kNoDepth - 1);
    for (std::size_t k = 0; k < q.size(); ++k) {  // a surface beyond 131 m stays one, at 131 m
      q[k] = std::isfinite(z[k])
                 ? static_cast<std::uint16_t>(std::lround(std::clamp(z[k] / ViewMemory::kDepthStepM, 0.0f, kMaxSteps)))
                 : ViewMemory::kNoDepth;
    }
    memory->T_W_C = T_W_C;
    memory->vertices = static_cast<std::uint32_t>(mesh.vertexCount());
  }
  stats.depth_ms = clock.elapsedMs();

  // 3. Each vertex of those voxels: its pixel, colour (bilinear) and geometric residual.
  clock.reset();
  const ImageF32& z_ref = reference.depth;
  std::vector<Candidate> candidates = gatherCandidates(map, mesh, voxels, ViewSampler(view, T_W_C, params_),
                                                       [&z_ref](int u, int v) { return z_ref.at(u, v); });
  for (const Candidate& c : candidates) stats.vertices_in_view += c.valid ? 1 : 0;

  // 4. The exposure gain: median of observed / mapped luminance over coloured, unoccluded vertices.
  double gain = 1.0;
  if (params_.exposure_gain) {
    std::vector<float> ratios;
    for (const Candidate& c : candidates) {
      if (!c.sampled || c.r_geom > static_cast<float>(params_.sigma_geom) || !mesh.hasColour(c.vertex)) continue;
      const float mapped = luminance(mesh.colourMean(c.vertex));
      const float seen = luminance(c.colour);
      if (mapped > 0.02f && seen > 0.02f) ratios.push_back(seen / mapped);
    }
    if (ratios.size() >= 100) {
      std::nth_element(ratios.begin(), ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2), ratios.end());
      gain = std::clamp(static_cast<double>(ratios[ratios.size() / 2]), 0.25, 4.0);
    }
  }
  stats.gain = gain;
  if (memory != nullptr) memory->gain = gain;

  // 5. eq. 9-10: W of every candidate, against the colour means before this view's update.
  weigh(candidates, mesh, params_, gain);

  // 6. The updates, texture and semantics side by side; every candidate is a distinct vertex.
  const auto fuse_texture = [&] { fuseColours(candidates, mesh, params_); };
  const auto refine_semantics = [&] {
    // A vertex this frame's LiDAR saw through (every return around its pixel lies well behind it)
    // was not there when the image was taken, such as the trail a moving car left: the pixel shows
    // what lies behind, so it says nothing of the vertex's class.
    const bool lidar = input.points_L != nullptr && params_.lidar_window_px >= 0;
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
    const FrameGround ground = input.points_L != nullptr ? FrameGround(*input.points_L, T_W_L) : FrameGround();
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

RefinementStats Refinement::revisit(SemanticMesh& mesh, const CameraView& view, const ViewMemory& memory) {
  RefinementStats stats;
  if (memory.empty() || !view.hasImage() || view.image.channels() < 3) return stats;
  if (memory.depth.width() != view.image.width() || memory.depth.height() != view.image.height()) {
    throw std::invalid_argument("refinement: a revisited view's depth is " + std::to_string(memory.depth.width()) +
                                "x" + std::to_string(memory.depth.height()) + " but its image " +
                                std::to_string(view.image.width()) + "x" + std::to_string(view.image.height()));
  }
  const auto end = static_cast<std::uint32_t>(mesh.vertexCount());
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
      if (sampler.sample(mesh.positions()[v], c, depth_at)) mine.push_back(c);
    }
  });
  std::vector<Candidate> candidates;
  for (const std::vector<Candidate>& mine : found) candidates.insert(candidates.end(), mine.begin(), mine.end());
  stats.vertices_in_view = candidates.size();
  stats.gain = memory.gain;
  weigh(candidates, mesh, params_, memory.gain);
  fuseColours(candidates, mesh, params_);
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
