#include "artemis/mapping/incremental_mesher.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "delaunay.hpp"

namespace artemis::mapping {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector3f;

IncrementalMesher::IncrementalMesher(const MesherParams& params)
    : params_(params),
      min_sin_angle_(std::sin(params.min_angle_deg * std::numbers::pi / 180.0)),
      min_cos_plane_(std::cos(params.max_plane_angle_deg * std::numbers::pi / 180.0)) {}

namespace {

// Smallest angle's sine of triangle abc, from its edge vectors (0 for degenerate triangles).
double minSinAngle(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d ab = b - a;
  const Vector3d bc = c - b;
  const Vector3d ca = a - c;
  const double twice_area = ab.cross(-ca).norm();
  const double lab = ab.norm();
  const double lbc = bc.norm();
  const double lca = ca.norm();
  if (twice_area <= 0.0 || lab <= 0.0 || lbc <= 0.0 || lca <= 0.0) return 0.0;
  // sin(angle at a) = 2A / (|ab| |ca|), and so on; the smallest angle is opposite the shortest edge.
  return std::min({twice_area / (lab * lca), twice_area / (lab * lbc), twice_area / (lbc * lca)});
}

}  // namespace

VoxelPlane fitVoxelPlane(const std::vector<Vector3f>& points, const MesherParams& params) {
  VoxelPlane plane;
  if (points.size() < 3) return plane;
  for (const Vector3f& p : points) plane.centroid += p.cast<double>();
  plane.centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vector3f& p : points) {
    const Vector3d d = p.cast<double>() - plane.centroid;
    covariance += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  const Vector3d lambda = eigen.eigenvalues().cwiseMax(0.0);  // ascending
  if (!(lambda(2) > 0.0) || lambda(1) < params.linear_ratio * lambda(2)) return plane;
  plane.line = false;
  plane.normal = eigen.eigenvectors().col(0);
  plane.major = eigen.eigenvectors().col(2);
  plane.planar = lambda(0) <= params.nonplanar_ratio * lambda(1);
  return plane;
}

VoxelMeshResult IncrementalMesher::meshVoxel(const VoxelMap& map, const SemanticMesh& mesh, const VoxelKey& key) const {
  VoxelMeshResult result;
  result.key = key;
  const Voxel* voxel = map.find(key);
  if (voxel == nullptr || static_cast<int>(voxel->vertices.size()) < params_.min_points) return result;
  const auto& views = mesh.viewDirections();

  // Plane of the voxel's own points (PCA), the normal turned to the side the sensors saw it from
  // (a few view directions suffice).
  const VoxelPlane plane = fitVoxelPlane(voxel->points, params_);
  if (plane.line) return result;
  Vector3d view = Vector3d::Zero();
  for (std::size_t i = 0; i < voxel->vertices.size(); i += 1 + voxel->vertices.size() / 8) {
    view += views[voxel->vertices[i]].cast<double>();
  }
  const Vector3d& centroid = plane.centroid;
  const Vector3d normal = plane.normal.dot(view) < 0.0 ? Vector3d(-plane.normal) : plane.normal;
  const bool planar = plane.planar;
  const bool upright = !(std::abs(normal.z()) > kLevelNormalZ);
  const double max_edge = !planar   ? params_.max_edge_nonplanar_m
                          : upright ? std::min(params_.max_edge_m, params_.max_edge_upright_m)
                                    : params_.max_edge_m;
  const Vector3d& u = plane.major;
  const Vector3d w = normal.cross(u);

  // Own points, then the rim: neighbours' points within rim_m of this voxel's box.
  // Per-thread scratch: meshing thousands of voxels a frame should not mean thousands of mallocs.
  thread_local std::vector<std::uint32_t> ids;
  thread_local std::vector<Vector3f> points;
  thread_local std::vector<Vector2d> projected;
  ids.assign(voxel->vertices.begin(), voxel->vertices.end());
  points.assign(voxel->points.begin(), voxel->points.end());
  const float size = map.voxelSize();
  const Vector3f lo = Vector3f(static_cast<float>(key.x), static_cast<float>(key.y), static_cast<float>(key.z)) * size -
                      Vector3f::Constant(static_cast<float>(params_.rim_m));
  const Vector3f hi = lo + Vector3f::Constant(size + 2.0f * static_cast<float>(params_.rim_m));
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const Voxel* n = map.find({key.x + dx, key.y + dy, key.z + dz});
        if (n == nullptr || (n->hi.array() < lo.array()).any() || (n->lo.array() > hi.array()).any()) continue;
        for (std::size_t i = 0; i < n->points.size(); ++i) {
          const Vector3f& p = n->points[i];
          if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) {
            ids.push_back(n->vertices[i]);
            points.push_back(p);
          }
        }
      }
    }
  }

  projected.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vector3d d = points[i].cast<double>() - centroid;
    projected[i] = Vector2d(d.dot(u), d.dot(w));
  }
  const auto triangles = detail::delaunay2d(projected);

  const float inv_size = 1.0f / size;
  for (const auto& t : triangles) {
    const auto ia = static_cast<std::size_t>(t[0]);
    const auto ib = static_cast<std::size_t>(t[1]);
    const auto ic = static_cast<std::size_t>(t[2]);
    const std::uint32_t a = ids[ia];
    const std::uint32_t b = ids[ib];
    const std::uint32_t c = ids[ic];
    // Centroid summed in vertex-id order, so that every voxel computes the same bits for the same
    // face and exactly one owns it.
    std::array<std::pair<std::uint32_t, std::size_t>, 3> sorted{{{a, ia}, {b, ib}, {c, ic}}};
    std::sort(sorted.begin(), sorted.end());
    const Vector3f centre = (points[sorted[0].second] + points[sorted[1].second] + points[sorted[2].second]) / 3.0f;
    // The owner is the voxel holding the centroid; when that voxel has no points (and so never
    // meshes), the voxel of origin of the face's smallest vertex id: the same rule everywhere.
    // This voxel exists, so only a face whose fallback is this voxel needs the centroid's looked up.
    const VoxelKey holder = voxelKeyOf(centre, inv_size);
    if (!(holder == key) && !(mesh.voxels()[sorted[0].first] == key && map.find(holder) == nullptr)) continue;
    const Vector3d pa = points[ia].cast<double>();
    const Vector3d pb = points[ib].cast<double>();
    const Vector3d pc = points[ic].cast<double>();
    if ((pb - pa).norm() > max_edge || (pc - pb).norm() > max_edge || (pa - pc).norm() > max_edge) continue;
    if (minSinAngle(pa, pb, pc) < min_sin_angle_) continue;
    Vector3d face_normal = (pb - pa).cross(pc - pa);
    const double length = face_normal.norm();
    if (length <= 0.0) continue;
    face_normal /= length;
    const double cos_plane = face_normal.dot(normal);
    if (std::abs(cos_plane) < min_cos_plane_) continue;
    // Wind so that the face normal points to the sensor side of the plane.
    result.faces.push_back(cos_plane > 0.0 ? Face{a, b, c} : Face{a, c, b});
  }
  result.normal = normal.cast<float>();
  result.planar = planar;
  return result;
}

}  // namespace artemis::mapping
