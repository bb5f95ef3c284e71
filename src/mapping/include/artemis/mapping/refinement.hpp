#pragma once
// Stage 2 of the Living Map (paper §III-C), texture part: for the vertices the camera sees, a
// reliability W from photometric and geometric residuals (eq. 9-11) weighs a Bayesian update of
// each vertex's Gaussian colour.
//
//   W = exp(-1/2 ((r_photo / sigma_photo)^2 + (r_geom / sigma_geom)^2))                    (eq. 9)
//   r_photo = || c(u, v) / g - mu^- ||                                                      (eq. 10)
//   r_geom = |d_proj - d_ref| / max(d_ref, epsilon)                                         (eq. 11)
//
// How the symbols are read here:
//   c(u, v)  the pixel's colour at the vertex's sub-pixel projection (bilinear), in linear RGB
//            (the image's sRGB decoded), 0..1; g the frame's exposure gain against the map (the
//            median over well-placed, already coloured vertices of observed / mapped luminance).
//   mu^-     the vertex's colour mean before the update; a vertex without colour has r_photo = 0.
//   d_proj   the vertex's depth in the camera; d_ref the depth of the reference depth map at its
//            pixel: the z-buffer of the current mesh rendered from the camera (render module),
//            which settles occlusion. Where the z-buffer has no face, r_geom = 0.
// Vertices with W below min_reliability are not updated. The colour is a Gaussian per channel:
// an observation enters with variance sigma_obs^2 / W (a Kalman update of mean and variance).
//
// Culling costs in proportion to what is visible: the voxel map's 6.4 m blocks are tested against
// the view frustum first, then the voxels of the blocks in view; only their faces are rendered and
// only their vertices updated. Results do not depend on the thread count.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/frame.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis::mapping {

struct RefinementParams {
  double sigma_photo = 0.15;     // eq. 9, linear RGB (0..1)
  double sigma_geom = 0.02;      // eq. 9, relative depth
  double depth_epsilon_m = 1.0;  // eq. 11
  double min_reliability = 0.1;  // W below this: no update
  double sigma_obs = 0.05;       // colour observation noise at W = 1, linear RGB
  bool reliability = true;       // false: W = 1 for every visible vertex in front (plain averaging)
  bool exposure_gain = true;     // false: gain 1
  double max_range_m = 80.0;     // voxels farther from the camera are not refined
};

struct RefinementStats {
  std::size_t blocks_in_view = 0;
  std::size_t voxels_in_view = 0;
  std::size_t faces_rendered = 0;
  std::size_t vertices_in_view = 0;  // projected into the image, in front of the camera
  std::size_t vertices_updated = 0;  // W >= min_reliability
  double gain = 1.0;
  double cull_ms = 0.0;
  double depth_ms = 0.0;
  double fuse_ms = 0.0;
};

// The voxels of `map` whose bounds may be in the view: blocks first, then voxels. Indices into
// the map, ascending.
std::vector<std::uint32_t> voxelsInView(const VoxelMap& map, const PinholeCamera& camera, const Isometry3d& T_W_C,
                                        double max_range_m);

class TextureRefinement {
 public:
  explicit TextureRefinement(const RefinementParams& params);

  // Refines the colours of the vertices `view` sees from the LiDAR pose `T_W_L`.
  RefinementStats refine(const VoxelMap& map, SemanticMesh& mesh, const CameraView& view, const Isometry3d& T_W_L);

  [[nodiscard]] const RefinementParams& params() const { return params_; }

 private:
  RefinementParams params_;
};

}  // namespace artemis::mapping
