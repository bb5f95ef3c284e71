#pragma once
// Stage 1b: 2-D masks into the map (paper eq. 1). Every LiDAR point of the frame that projects into
// the segmented image is an observation of the class at its pixel (the mask's class, or "none of
// the prompted classes" outside every mask) for the cell the point fell in, with weight
//
//   omega = sigma_mask * cos(theta_view) * exp(-d_depth / sigma_d)                        (eq. 1)
//
// How the symbols are read here:
//   sigma_mask  the score of the mask the pixel belongs to; outside every mask, background_score.
//   theta_view  the angle between the camera's ray to the point and the surface normal of the
//               point's cell (the vertex normal: the voxel's fitted plane once meshed, until then
//               the direction to the sensor); |cos|, so either side of the plane counts.
//   d_depth     the point's depth minus the smallest LiDAR depth projected within depth_window_px
//               of its pixel: ~0 on an open surface, large for a point just behind a nearer
//               object's silhouette, where masks bleed across the occlusion edge.
//   sigma_d     sigma_depth_m.
// A point that lies well behind a nearer return of the same object class (or mask) within a few
// pixels observes nothing (omega = 0): its pixel shows the object's mask spilling past the
// object's silhouette (ObjectSilhouettes; geometry.silhouettes).
//
// "Each voxel maintains a semantic probability distribution": each observation goes to the
// meshing voxel (0.4 m: the paper's voxel, whose W_sem gives eq. 7's confidence) and to the cell
// of the point (the sub-cell, 0.1 m, which holds exactly one mesh vertex). The voxel alone is too
// coarse for labels (a car's sill and the road under it share one); the cell alone leaves the
// vertices the camera never saw unlabelled. A vertex's distribution is therefore its cell's
// evidence plus its voxel's distribution weighted by voxel_prior (SemanticMesh). Distributions
// are confidence-weighted averages of one-hot observations: evidence per class / W_sem.
//
// A dense observation (per-pixel probabilities) adds, instead of one class, the pixel's whole
// distribution weighed by the geometry of the point (DenseEvidence: its height above this frame's
// ground, FrameGround), with sigma_mask the largest of those probabilities: an unsure pixel
// weighs less, and a "car" pixel on the road at road level mostly says "none".

#include <cstdint>
#include <functional>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/core/projection.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/mapping/frame_ground.hpp"
#include "artemis/mapping/geometric_prior.hpp"
#include "artemis/mapping/object_silhouettes.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_map.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::mapping {

struct SemanticFusionParams {
  // sigma_d of eq. 1, metres.
  double sigma_depth_m = 0.5;
  // Half-size of the pixel neighbourhood whose nearest LiDAR depth d_depth is measured against.
  int depth_window_px = 3;
  // sigma_mask of the background observation (pixels outside every mask).
  double background_score = 0.5;
  // lambda of eq. 7 (xi = 1 - exp(-lambda W_sem)).
  double confidence_lambda = 0.5;
  // Weight of the voxel's distribution in each of its vertices' (the cell's evidence adds to it).
  double voxel_prior = 10.0;
  // What the geometry says of each class, for dense observations (fusion and refinement).
  GeometricPriorParams geometry;
};

struct FusionStats {
  std::size_t points_in_image = 0;  // points of the frame that project into the image
  std::size_t observations = 0;     // of those, with a cell and a weight > 0
  double ms = 0.0;
};

class SemanticFusion {
 public:
  explicit SemanticFusion(const SemanticFusionParams& params);

  // Fuses the frame's observation into `mesh`: `points_L` are the points the last insert() into
  // `map` took, with pose `T_W_L`; each observes the cell (the vertex) its point fell in. Only the points that
  // project into the image are looked at. Classes of the observation's masks must have slots in
  // `mesh` (SemanticMesh::addSemanticClass).
  // `vocabulary` names the classes for the geometric prior of dense observations (nullptr:
  // SemanticKITTI's).
  FusionStats fuse(const PointCloud& points_L, const VoxelMap& map, const Isometry3d& T_W_L, const CameraView& view,
                   const semantics::SemanticObservation& observation, SemanticMesh& mesh,
                   const semantics::Vocabulary* vocabulary = nullptr);

  // The same for an observation that arrives after its frame was inserted (a segmenter running
  // behind the mapper): each point observes the vertex the map now holds in its cell.
  FusionStats fuseLate(const PointCloud& points_L, const VoxelMap& map, const Isometry3d& T_W_L, const CameraView& view,
                       const semantics::SemanticObservation& observation, SemanticMesh& mesh,
                       const semantics::Vocabulary* vocabulary = nullptr);

  [[nodiscard]] const SemanticFusionParams& params() const { return params_; }

 private:
  // The vertex point i observes (VoxelMap::kNoVertex: none).
  using VertexOf = std::function<std::uint32_t(std::size_t)>;
  FusionStats fuseWith(const VertexOf& vertex_of, const PointCloud& points_L, const Isometry3d& T_W_L,
                       const CameraView& view, const semantics::SemanticObservation& observation, SemanticMesh& mesh,
                       const semantics::Vocabulary* vocabulary);
  FusionStats fuseDense(const VertexOf& vertex_of, const PointCloud& points_L, const Isometry3d& T_W_L,
                        const CameraView& view, const semantics::SemanticObservation& observation, SemanticMesh& mesh,
                        const semantics::Vocabulary& vocabulary);
  // The object silhouettes of the frame's returns projected into projected_ (w x h).
  void buildSilhouettes(const PointCloud& points_L, const Isometry3d& T_W_L, const FrameGround& ground,
                        const ObjectSilhouettes::LabelOf& label_of, int w, int h);
  // d_depth of eq. 1 for a projected point: its depth minus the nearest within the window.
  [[nodiscard]] float depthGap(const DepthProjection::Point& q, int w, int h) const;

  SemanticFusionParams params_;
  DepthProjection projected_;  // per-frame scratch
  ObjectSilhouettes silhouettes_;
};

}  // namespace artemis::mapping
