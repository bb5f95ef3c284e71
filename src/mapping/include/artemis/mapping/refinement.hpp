#pragma once
// Stage 2 of the Living Map (paper §III-C): for the vertices the camera sees, a reliability W from
// photometric and geometric residuals (eq. 9-11) weighs a Bayesian update of each vertex's
// Gaussian colour and, with the same W, a log-probability update of its classes (eq. 12-13).
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
//            which settles occlusion, checked against the frame's LiDAR depth: d_ref is the nearer
//            of the z-buffer and the nearest LiDAR return within lidar_window_px. A LiDAR mesh has
//            holes (windows, foliage, thin poles) through which hidden vertices would show; the
//            LiDAR sees the occluder even where it was never meshed. The window also marks the
//            pixels just beside a nearer silhouette, where masks bleed and colours mix. On the
//            simulated street (200 frames, standard masks) the LiDAR check moved in-frustum
//            car / building / vegetation IoU of the refined run from 95.5 / 95.9 / 89.7 to
//            96.7 / 96.5 / 92.0 (window 2; 1 and 3 are within 0.4). Where neither has a depth,
//            r_geom = 0.
// Vertices with W below min_reliability are not updated. The colour is a Gaussian per channel:
// an observation enters with variance sigma_obs^2 / W (a Kalman update of mean and variance).
//
//   lambda_i,c += W_i log P_mask(o_i | c)                                              (eq. 12-13)
//
// o_i is the mask at the vertex's pixel (nearest). Inside a mask of class c_m with score s:
// P_mask(o | c_m) = s and (1 - s) / (slots - 1) for every other slot; outside every mask the
// observation is "none of the prompted classes" with stage 1's background score (one setting for
// both stages: SemanticFusionParams::background_score). Every P_mask is floored at
// mask_floor so that the log stays finite. The read-out (SemanticMesh::distribution) is the
// softmax of lambda plus kappa times the log of stage 1's distribution.
// A dense observation gives P_mask(o | c) per slot directly: the pixel's probabilities weighed by
// the vertex's geometry (DenseEvidence: height above the frame's ground and its normal), floored
// at mask_floor. Bleeding at silhouettes is left to W: the LiDAR depth window gives a vertex just
// behind a nearer object's edge a large r_geom.
//
// W is computed for every visible vertex first; the texture and the semantic updates then run in
// parallel (each vertex is one voxel's, so the updates of different vertices never meet).
//
// A view sees surface the LiDAR meshes only later (a forward camera sees the road and walls ahead
// long before the vehicle is near enough to mesh them), so a textured view may be kept after its
// refinement and revisited (revisit()): it then colours the vertices added to the map since that
// are still without colour, with the same W and update, against the reference depth of its
// refinement. A new vertex where that depth had a nearer surface is hidden; one where it had a
// farther surface is turned away too (r_geom cannot tell a new occluder from a new surface behind
// it), and one where it had none takes the view's colour. Each view observes each vertex at most once.
//
// Culling costs in proportion to what is visible: the voxel map's 6.4 m blocks are tested against
// the view frustum first, then the voxels of the blocks in view; only their faces are rendered and
// only their vertices updated. Results do not depend on the thread count.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/frame.hpp"
#include "artemis/core/image.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/core/projection.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/mapping/geometric_prior.hpp"
#include "artemis/mapping/object_silhouettes.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_map.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::mapping {

struct RefinementParams {
  // eq. 9. Measured by held-out PSNR (artemis eval texture, every 5th view held out): on the
  // simulated street (200 frames) sigma_photo 0.15 / 0.3 / 0.6 / 10 gave 18.81 / 18.83 / 19.01 /
  // 19.01 dB and on KITTI drive 0013 (frames 0-49) 0.15 / 0.6 gave 12.45 / 12.53 dB: a tight
  // sigma_photo locks a vertex onto its first, farthest (blurriest) views; 0.6 still turns away
  // a colour that differs from the mean by the whole range (W 0.25 at 0.6 alone). sigma_geom 0.01 /
  // 0.02 / 0.05 were within 0.02 dB of each other; with 0.02 (2 % of the depth) a vertex 0.4 m
  // behind a surface 20 m away keeps W 0.61 and one 1 m behind gets 0.04 (below min_reliability).
  double sigma_photo = 0.6;         // linear RGB (0..1)
  double sigma_geom = 0.02;         // relative depth
  double depth_epsilon_m = 1.0;     // eq. 11
  double min_reliability = 0.1;     // W below this: no update
  double sigma_obs = 0.05;          // colour observation noise at W = 1, linear RGB
  bool reliability = true;          // false: W = 1 for every visible vertex in front (plain averaging)
  bool exposure_gain = true;        // false: gain 1
  bool semantic_refinement = true;  // false: the classes stay stage 1's (eq. 1, 7)
  double mask_floor = 0.01;         // eq. 13: P_mask is at least this
  // kappa: stage 1's distribution counts as this many views in the read-out (SemanticMesh).
  double stage_one_weight = 5.0;
  int lidar_window_px = 2;    // d_ref: the least of the z-buffer and the LiDAR depth within this; -1: z-buffer only
  int mask_border_px = 4;     // eq. 13: pixels this close to another mask (or none) observe nothing
  double max_range_m = 80.0;  // voxels farther from the camera are not refined
};

struct RefinementStats {
  std::size_t blocks_in_view = 0;
  std::size_t voxels_in_view = 0;
  std::size_t faces_rendered = 0;
  std::size_t vertices_in_view = 0;   // projected into the image, in front of the camera
  std::size_t vertices_updated = 0;   // W >= min_reliability: colours updated
  std::size_t vertices_labelled = 0;  // W >= min_reliability: classes updated (eq. 12-13)
  double gain = 1.0;
  double cull_ms = 0.0;
  double depth_ms = 0.0;
  double fuse_ms = 0.0;  // residuals, W, texture and semantic updates
  // Indices into the map of the voxels in view: those whose vertices may have new colours or classes.
  std::vector<std::uint32_t> voxels;
};

// What a refined view keeps for its revisit: the reference depth of its refinement in 2 mm steps
// (kNoDepth where none; a surface beyond 131 m is kept at 131 m), its exposure gain and camera
// pose, and how far the map was then.
struct ViewMemory {
  static constexpr std::uint16_t kNoDepth = 0xFFFF;
  static constexpr float kDepthStepM = 0.002f;  // 131 m at most, farther than max_range_m
  ImageU16 depth;
  double gain = 1.0;
  Isometry3d T_W_C = Isometry3d::Identity();
  std::uint32_t vertices = 0;  // the mesh's vertex count then: vertices with larger ids are new to the view
  [[nodiscard]] bool empty() const { return depth.empty(); }
};

// What one view refines: its colours (unless the frame is held out of texturing) and, when the
// frame was segmented, its classes.
struct RefinementInput {
  const CameraView* view = nullptr;
  bool texture = true;
  const semantics::SemanticObservation* observation = nullptr;  // nullptr: no semantic update
  const PointCloud* points_L = nullptr;                         // the frame's LiDAR points: checks the reference depth
  ViewMemory* memory = nullptr;  // when given and the view is textured: filled for a later revisit()
  const semantics::Vocabulary* vocabulary = nullptr;  // names the classes of a dense observation
};

// What a view's refinement reads of the map, taken first (Refinement::look): the voxels in view,
// their faces and their vertices (voxel after voxel), and the mesh's vertex count then. The rest
// of the refinement reads only those vertices' positions and the colours, and writes colours (and
// classes, with an observation): it can run while the next frame's points go in, which only adds
// vertices (Mapper::handOver).
struct ViewLook {
  bool refines = false;  // false: the view has nothing to refine (no image, no texture and no classes)
  std::vector<std::uint32_t> voxels;
  std::vector<Face> faces;
  std::vector<std::uint32_t> vertices;
  std::size_t vertex_count = 0;
  double cull_ms = 0.0;
  double copy_ms = 0.0;  // faces and vertices
};

// The voxels of `map` whose bounds may be in the view: blocks first, then voxels. Indices into
// the map, ascending.
std::vector<std::uint32_t> voxelsInView(const VoxelMap& map, const PinholeCamera& camera, const Isometry3d& T_W_C,
                                        double max_range_m);

class Refinement {
 public:
  // `background_score`: P_mask(none | outside every mask), in [0, 1].
  // `geometry`: the geometric prior of dense observations (one setting with stage 1's).
  explicit Refinement(const RefinementParams& params, double background_score = 0.5,
                      const GeometricPriorParams& geometry = {});

  // Refines the colours and classes of the vertices `input.view` sees from the LiDAR pose `T_W_L`:
  // look(), then refine() of what it took.
  RefinementStats refine(const VoxelMap& map, SemanticMesh& mesh, const RefinementInput& input,
                         const Isometry3d& T_W_L);
  // The refinement's look at the map (see ViewLook). Throws std::invalid_argument when the image
  // and the camera disagree in size.
  [[nodiscard]] ViewLook look(const VoxelMap& map, const SemanticMesh& mesh, const RefinementInput& input,
                              const Isometry3d& T_W_L) const;
  // The rest: `positions` are the mesh's first look.vertex_count vertex positions.
  RefinementStats refine(const ViewLook& look, std::span<const Eigen::Vector3f> positions, SemanticMesh& mesh,
                         const RefinementInput& input, const Isometry3d& T_W_L);

  // Colours, from `view` refined earlier with `memory`, the vertices added to the mesh since that
  // are still without colour and that it sees (texture only: its classes were taken once). The
  // camera pose is the memory's. Costs in proportion to the vertices added since: the mesh's
  // vertices, or those of `positions` (the mesh's first vertices).
  RefinementStats revisit(SemanticMesh& mesh, const CameraView& view, const ViewMemory& memory) {
    return revisit(mesh, view, memory, mesh.positions());
  }
  RefinementStats revisit(SemanticMesh& mesh, const CameraView& view, const ViewMemory& memory,
                          std::span<const Eigen::Vector3f> positions);

  [[nodiscard]] const RefinementParams& params() const { return params_; }

 private:
  RefinementParams params_;
  double background_score_;
  GeometricPriorParams geometry_;
  ObjectSilhouettes silhouettes_;  // per-view scratch of the semantic update
  DepthProjection lidar_;  // per-frame scratch
};

}  // namespace artemis::mapping
