#pragma once
// Appends tessellated primitives to a SceneMesh, each face tagged with the current class,
// instance, material and object. Faces are wound counter-clockwise seen from outside.

#include <Eigen/Geometry>

#include "artemis/sim/scene.hpp"

namespace artemis::sim::detail {

class MeshBuilder {
 public:
  MeshBuilder(SceneMesh& mesh, double max_edge_m) : mesh_(mesh), max_edge_m_(max_edge_m) {}

  void setTag(std::uint16_t class_id, std::uint16_t instance_id, Material material, std::uint32_t object) {
    class_id_ = class_id;
    instance_id_ = instance_id;
    material_ = material;
    object_ = object;
  }
  void setMaterial(Material material) { material_ = material; }
  void setClass(std::uint16_t class_id) { class_id_ = class_id; }
  // Tessellation edge for what follows (small objects use a finer one).
  void setMaxEdge(double max_edge_m) { max_edge_m_ = max_edge_m; }
  [[nodiscard]] double maxEdge() const { return max_edge_m_; }

  // Quad a-b-c-d (counter-clockwise from outside), as a grid of triangles no longer than maxEdge().
  void quad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d);

  // Box [lo, hi] in the frame T_S_P. Without `with_bottom` the face at z = lo.z is left out
  // (objects standing on the ground).
  void box(const Eigen::Isometry3d& T_S_P, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
           bool with_bottom = false);

  // A box whose top rectangle [top_lo, top_hi] (x, y) at z1 differs from its bottom one at z0:
  // car cabins, torsos.
  void frustum(const Eigen::Isometry3d& T_S_P, const Eigen::Vector2d& bottom_lo, const Eigen::Vector2d& bottom_hi,
               double z0, const Eigen::Vector2d& top_lo, const Eigen::Vector2d& top_hi, double z1, bool with_bottom);

  // Closed cylinder along the frame's z axis from z0 to z1.
  void cylinder(const Eigen::Isometry3d& T_S_P, double radius_m, double z0, double z1);

  // Ellipsoid centred at the frame origin with radii (rx, ry, rz).
  void ellipsoid(const Eigen::Isometry3d& T_S_P, const Eigen::Vector3d& radii);

 private:
  std::uint32_t addVertex(const Eigen::Vector3d& p_S);
  void addTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c);
  [[nodiscard]] int segments(double length_m, int min_segments) const;

  SceneMesh& mesh_;
  double max_edge_m_;
  std::uint16_t class_id_ = 0;
  std::uint16_t instance_id_ = 0;
  Material material_ = Material::kAsphalt;
  std::uint32_t object_ = 0;
};

}  // namespace artemis::sim::detail
