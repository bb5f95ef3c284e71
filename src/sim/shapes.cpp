// Road users' shapes: boxes, frustums, cylinders and ellipsoids, coarse enough for a LiDAR and a
// 1242-pixel camera to tell a sedan from a van and a person from a pole.

#include "shapes.hpp"

#include <cmath>
#include <numbers>

namespace artemis::sim::detail {

using Eigen::Isometry3d;
using Eigen::Vector3d;

Isometry3d frameAt(const Vector3d& p, double yaw) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = p;
  return T;
}

void carShape(MeshBuilder& builder, const Isometry3d& T, int variant, double len, double width) {
  struct Shape {
    double body_z0, body_z1, cabin_z1, cabin_b0, cabin_b1, cabin_t0, cabin_t1;
  };
  const Shape shapes[] = {
      {0.28, 0.85, 1.42, -0.26, 0.22, -0.2, 0.1},    // sedan: cabin over the middle
      {0.28, 0.88, 1.48, -0.46, 0.22, -0.44, 0.06},  // hatchback: cabin to the rear
      {0.32, 1.00, 1.85, -0.47, 0.25, -0.46, 0.13},  // van: tall cabin
  };
  const Shape& s = shapes[variant];
  const double hl = len / 2;
  const double hw = width / 2;
  builder.setMaterial(Material::kCarBody);
  builder.setMaxEdge(0.25);
  builder.box(T, {-hl, -hw, s.body_z0}, {hl, hw, s.body_z1}, true);
  builder.setMaterial(Material::kCarCabin);
  builder.frustum(T, {s.cabin_b0 * len, -hw + 0.06}, {s.cabin_b1 * len, hw - 0.06}, s.body_z1,
                  {s.cabin_t0 * len, -hw + 0.2}, {s.cabin_t1 * len, hw - 0.2}, s.cabin_z1, false);
  wheels(builder, T, hl - 0.8, hw, 0.32, 0.22);  // tyres flush with the body: a car at the curb touches it
}

void wheels(MeshBuilder& builder, const Isometry3d& T, double axle_x, double outer_y, double radius,
            double tyre_width) {
  builder.setMaterial(Material::kRubber);
  builder.setMaxEdge(0.2);
  for (double x : {-axle_x, axle_x}) {
    for (int s : {1, -1}) {
      Isometry3d W = T;  // cylinder axis along the car's y
      W.linear() = T.linear() * Eigen::AngleAxisd(-s * std::numbers::pi / 2, Vector3d::UnitX()).toRotationMatrix();
      W.translation() = T * Vector3d(x, s * (outer_y - tyre_width), radius);
      builder.cylinder(W, radius, 0.0, tyre_width);
    }
  }
}

void truckShape(MeshBuilder& builder, const Isometry3d& T, double len) {
  const double hw = 1.25;
  builder.setMaterial(Material::kCarCabin);
  builder.setMaxEdge(0.3);
  builder.box(T, {len / 2 - 2.1, -hw + 0.05, 0.45}, {len / 2, hw - 0.05, 2.9}, true);
  builder.setMaterial(Material::kCarBody);
  builder.box(T, {-len / 2, -hw, 0.95}, {len / 2 - 2.3, hw, 3.6}, true);
  builder.box(T, {-len / 2 + 0.3, -0.5, 0.5}, {len / 2 - 2.1, 0.5, 0.95}, true);  // chassis
  wheels(builder, T, len / 2 - 1.2, hw - 0.05, 0.5, 0.3);
}

void personShape(MeshBuilder& builder, const Vector3d& base, double yaw, double height_m) {
  const double H = height_m;
  const Isometry3d T = frameAt(base, yaw);
  builder.setMaxEdge(0.12);
  builder.box(T, {-0.08, -0.17, 0.0}, {0.08, -0.03, 0.47 * H});
  builder.box(T, {-0.08, 0.03, 0.0}, {0.08, 0.17, 0.47 * H});
  builder.frustum(T, {-0.1, -0.17}, {0.1, 0.17}, 0.47 * H, {-0.12, -0.22}, {0.12, 0.22}, 0.82 * H, true);
  builder.box(T, {-0.05, -0.3, 0.45 * H}, {0.05, -0.23, 0.8 * H}, true);
  builder.box(T, {-0.05, 0.23, 0.45 * H}, {0.05, 0.3, 0.8 * H}, true);
  builder.ellipsoid(frameAt(T * Vector3d(0, 0, 0.905 * H), yaw), {0.09 * H * 0.6, 0.09 * H * 0.55, 0.095 * H});
}

void bicycleShape(MeshBuilder& builder, const Isometry3d& T) {
  builder.setMaxEdge(0.1);
  const double r = 0.34;
  for (double wx : {-0.52, 0.52}) {
    Isometry3d W = T;
    W.linear() = T.linear() * Eigen::AngleAxisd(-std::numbers::pi / 2, Vector3d::UnitX()).toRotationMatrix();
    W.translation() = T * Vector3d(wx, -0.02, r);
    builder.setMaterial(Material::kRubber);
    builder.cylinder(W, r, 0.0, 0.04);
  }
  builder.setMaterial(Material::kMetal);
  builder.box(T, {-0.52, -0.02, r - 0.02}, {0.1, 0.02, r + 0.02}, true);  // chain stay
  builder.box(T, {-0.1, -0.02, r}, {-0.05, 0.02, 0.85}, true);            // seat tube
  builder.box(T, {-0.1, -0.02, 0.72}, {0.45, 0.02, 0.76}, true);          // top tube
  builder.box(T, {0.42, -0.02, r}, {0.46, 0.02, 0.95}, true);             // fork and stem
  builder.box(T, {0.4, -0.28, 0.95}, {0.46, 0.28, 0.99}, true);           // handlebar
  builder.box(T, {-0.2, -0.08, 0.85}, {0.05, 0.08, 0.9}, true);           // saddle
}

void riderShape(MeshBuilder& builder, const Isometry3d& T, double height_m) {
  // Proportions of personShape, folded: hips on the saddle (z 0.9), legs down to the pedals,
  // torso leaning forward towards the handlebar (x 0.43, z 0.97), head above the shoulders.
  const double H = height_m;
  const double torso = 0.35 * H;
  builder.setMaterial(Material::kCloth);
  builder.setMaxEdge(0.12);
  for (double y : {-0.17, 0.03}) builder.box(T, {-0.12, y, 0.35}, {0.02, y + 0.14, 0.9}, true);  // legs
  Isometry3d lean = T;  // torso tilted 35 degrees forward about the hips
  lean.linear() = T.linear() * Eigen::AngleAxisd(0.61, Vector3d::UnitY()).toRotationMatrix();
  lean.translation() = T * Vector3d(-0.12, 0.0, 0.9);
  builder.frustum(lean, {-0.1, -0.17}, {0.1, 0.17}, 0.0, {-0.12, -0.21}, {0.12, 0.21}, torso, true);
  const Vector3d shoulder_P = T.inverse() * (lean * Vector3d(0.0, 0.0, 0.9 * torso));
  const Vector3d hand_P(0.43, 0.0, 0.97);
  const double reach = std::hypot(hand_P.x() - shoulder_P.x(), hand_P.z() - shoulder_P.z());
  Isometry3d arm = T;  // x along the arm, from the shoulder down to the hand
  arm.linear() = T.linear() * Eigen::AngleAxisd(-std::atan2(hand_P.z() - shoulder_P.z(), hand_P.x() - shoulder_P.x()),
                                                Vector3d::UnitY())
                                  .toRotationMatrix();
  arm.translation() = T * Vector3d(shoulder_P.x(), 0.0, shoulder_P.z());
  for (double y : {-0.25, 0.2}) builder.box(arm, {0.0, y, -0.03}, {reach, y + 0.05, 0.03}, true);
  builder.ellipsoid(lean * Isometry3d(Eigen::Translation3d(0.0, 0.0, torso + 0.1 * H)),
                    {0.09 * H * 0.6, 0.09 * H * 0.55, 0.095 * H});
}

}  // namespace artemis::sim::detail
