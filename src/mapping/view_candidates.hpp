#pragma once
// Refinement's view of the mesh (steps 3 and 5 of Refinement::refine, DESIGN.md): each vertex a
// view sees, its pixel, colour and geometric residual (ViewSampler, gatherCandidates), its
// reliability W (eq. 9-10, weigh) and the colour update (fuseColours). Internal to mapping.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>

#include "artemis/core/frame.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/mapping/refinement.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis::mapping::detail {

// sRGB (8-bit) to linear RGB.
const std::array<float, 256>& srgbToLinear();
float luminance(const Eigen::Vector3f& c);

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
float hiddenResidual(const RefinementParams& params);

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

// Step 3 for each of `vertices` (at `positions`, by id), in their order.
template <typename DepthAt>
std::vector<Candidate> gatherCandidates(std::span<const Eigen::Vector3f> positions,
                                        const std::vector<std::uint32_t>& vertices, const ViewSampler& sampler,
                                        const DepthAt& depth_at) {
  std::vector<Candidate> candidates(vertices.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices.size(), 1024), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      Candidate& c = candidates[k];
      c.vertex = vertices[k];
      sampler.sample(positions[c.vertex], c, depth_at);
    }
  });
  return candidates;
}

// Step 4: the view's exposure gain, the median of observed / mapped luminance over the candidates
// that are coloured, sampled and unoccluded (r_geom up to sigma_geom), clamped to [0.25, 4]; 1
// with fewer than 100 of them.
double exposureGain(const std::vector<Candidate>& candidates, const SemanticMesh& mesh, const RefinementParams& params);

// Step 5: eq. 9-10, W of every candidate against the colour means before the update (the colours
// divided by the view's gain first); below min_reliability W is 0.
void weigh(std::vector<Candidate>& candidates, const SemanticMesh& mesh, const RefinementParams& params, double gain);

// The colour update: an observation with variance sigma_obs^2 / W; every candidate is a distinct
// vertex, one of the mesh's first `vertices`.
void fuseColours(const std::vector<Candidate>& candidates, SemanticMesh& mesh, const RefinementParams& params,
                 std::size_t vertices);

}  // namespace artemis::mapping::detail
