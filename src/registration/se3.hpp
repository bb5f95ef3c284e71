#pragma once
// SE(3) exponential and logarithm for the registration module: a twist is (phi, rho), rotation
// vector then the translation part, with T = Exp(phi, rho) = [exp(phi), V(phi) rho].

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "artemis/core/transform.hpp"

namespace artemis::registration::se3 {

using Vector6d = Eigen::Matrix<double, 6, 1>;

inline Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// V(phi): the translation of Exp(phi, rho) is V(phi) rho.
inline Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d phi_hat = hat(phi);
  if (theta < 1e-9) return Eigen::Matrix3d::Identity() + 0.5 * phi_hat;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * phi_hat +
         (theta - std::sin(theta)) / (t2 * theta) * phi_hat * phi_hat;
}

inline Vector6d log(const Isometry3d& T) {
  const Eigen::AngleAxisd rotation(T.linear());
  const Eigen::Vector3d phi = rotation.angle() * rotation.axis();
  Vector6d xi;
  xi << phi, leftJacobian(phi).inverse() * T.translation();
  return xi;
}

inline Isometry3d exp(const Vector6d& xi) {
  const Eigen::Vector3d phi = xi.head<3>();
  const double angle = phi.norm();
  Isometry3d T = Isometry3d::Identity();
  if (angle > 0.0) T.linear() = Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
  T.translation() = leftJacobian(phi) * xi.tail<3>();
  return T;
}

}  // namespace artemis::registration::se3
