#pragma once
// Meshes voxels one by one (paper §III-B): fit a plane to the voxel's points (PCA), project them
// and a rim of neighbour points onto it, triangulate in 2-D (Delaunay), drop triangles that are too
// long, too thin or too steep to the plane, lift them back to the 3-D points, and replace the
// voxel's old faces. A face belongs to the voxel that holds its centroid, so neighbouring voxels,
// which both see the points along their border, never both keep it: no duplicate faces and no
// seams at voxel borders. Faces are wound so that their normal points towards the sensor.
//
// Voxels that are not planar (a tree crown, scatter) are triangulated in their best-fit plane with
// a shorter edge limit, which keeps a leafy blob from growing sheets across its gaps, and so are
// upright planar ones, more mildly; points along a single line (one scan line, a thin pole seen
// edge-on) give no faces until more points arrive.

#include <vector>

#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis::mapping {

// A plane whose normal is this close to the world's vertical (|n_z| above it, ~45 deg) is level:
// the ground, a roof; below it, upright. The mesher's edge limits and the carver's rules split so.
inline constexpr float kLevelNormalZ = 0.7f;

struct MesherParams {
  double rim_m = 0.15;                // neighbour points this close to the voxel join its triangulation
  double max_edge_m = 0.6;            // longest edge of a face on a planar voxel
  double max_edge_nonplanar_m = 0.3;  // ... on a non-planar one
  // ... on a planar voxel that stands upright (its normal more than ~45 deg from vertical: a wall,
  // a hedge's face, a car's side). The scanner's beams lie far closer on such surfaces than on the
  // ground ahead (on KITTI within 30 m: ~0.2 m apart and less), so a longer edge there spans a gap:
  // foliage, an occlusion's shadow, a window. (KITTI 0013 0-49: precision at 0.1 m 0.9245 ->
  // 0.9298, recall 0.8745 -> 0.8739; the README's "Upright surfaces keep shorter edges".)
  double max_edge_upright_m = 0.4;
  double min_angle_deg = 4.0;         // thinner faces are dropped
  double max_plane_angle_deg = 60.0;  // faces tilted more than this from the voxel's plane are dropped
  double nonplanar_ratio = 0.04;      // lambda_min / lambda_mid above this: not planar
  double linear_ratio = 0.005;        // lambda_mid / lambda_max below this: points on a line
  int min_points = 3;
};

// The plane of a voxel's points (PCA), as the mesher fits it.
struct VoxelPlane {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, of either sign; zero for a line
  Eigen::Vector3d major = Eigen::Vector3d::Zero();   // the direction of largest spread
  bool line = true;                                  // no plane: too few points, or all along a line
  bool planar = false;                               // a plane, and the points lie on it (not scattered)
};
// Fits `points` with the ratios of `params` (linear_ratio, nonplanar_ratio); fewer than 3 points
// are a line.
VoxelPlane fitVoxelPlane(const std::vector<Eigen::Vector3f>& points, const MesherParams& params);

// What meshing one voxel produced.
struct VoxelMeshResult {
  VoxelKey key;
  std::vector<Face> faces;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // plane normal towards the sensor; zero if none
  bool planar = false;                               // the points lie on that plane (not scattered)
};

class IncrementalMesher {
 public:
  explicit IncrementalMesher(const MesherParams& params);

  // Meshes one voxel from the map's current points (read-only; safe to call from many threads).
  [[nodiscard]] VoxelMeshResult meshVoxel(const VoxelMap& map, const SemanticMesh& mesh, const VoxelKey& key) const;

  [[nodiscard]] const MesherParams& params() const { return params_; }

 private:
  MesherParams params_;
  double min_sin_angle_;
  double min_cos_plane_;
};

}  // namespace artemis::mapping
