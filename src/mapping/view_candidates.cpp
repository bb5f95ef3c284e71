#include "view_candidates.hpp"

#include <algorithm>

#include "artemis/core/colour.hpp"

namespace artemis::mapping::detail {

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

// Where a candidate's W must fall below min_reliability whatever its colour: r_geom / sigma_geom
// above sqrt(-2 ln min_reliability), with a margin for rounding, and never below sigma_geom (the
// exposure gain reads the colours of candidates up to sigma_geom). Its colour is then not sampled.
float hiddenResidual(const RefinementParams& params) {
  if (!params.reliability || !(params.min_reliability > 0.0)) return std::numeric_limits<float>::infinity();
  const double w_bound = params.sigma_geom * std::sqrt(-2.0 * std::log(params.min_reliability));
  return static_cast<float>(std::max(w_bound, params.sigma_geom) * (1.0 + 1e-4));
}

double exposureGain(const std::vector<Candidate>& candidates, const SemanticMesh& mesh,
                    const RefinementParams& params) {
  // Each range's ratios in parallel (a KITTI view has ~75,000 candidates: 1.6 ms in one loop), then
  // the median of all of them: the same value in any order.
  constexpr std::size_t kRange = 4096;
  std::vector<std::vector<float>> parts((candidates.size() + kRange - 1) / kRange);
  const auto sigma_geom = static_cast<float>(params.sigma_geom);
  tbb::parallel_for(std::size_t{0}, parts.size(), [&](std::size_t r) {
    for (std::size_t k = r * kRange; k < std::min(candidates.size(), (r + 1) * kRange); ++k) {
      const Candidate& c = candidates[k];
      if (!c.sampled || c.r_geom > sigma_geom || !mesh.hasColour(c.vertex)) continue;
      const float mapped = luminance(mesh.colourMean(c.vertex));
      const float seen = luminance(c.colour);
      if (mapped > 0.02f && seen > 0.02f) parts[r].push_back(seen / mapped);
    }
  });
  std::vector<float> ratios;
  for (const std::vector<float>& part : parts) ratios.insert(ratios.end(), part.begin(), part.end());
  if (ratios.size() < 100) return 1.0;
  std::nth_element(ratios.begin(), ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2), ratios.end());
  return std::clamp(static_cast<double>(ratios[ratios.size() / 2]), 0.25, 4.0);
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
void fuseColours(const std::vector<Candidate>& candidates, SemanticMesh& mesh, const RefinementParams& params,
                 std::size_t vertices) {
  const auto obs_var = static_cast<float>(params.sigma_obs * params.sigma_obs);
  mesh.reserveColours(vertices);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const Candidate& c = candidates[k];
      if (c.reliability > 0.0f) mesh.fuseColour(c.vertex, c.colour, obs_var / c.reliability);
    }
  });
}

}  // namespace artemis::mapping::detail
