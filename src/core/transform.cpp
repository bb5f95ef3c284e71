#include "artemis/core/transform.hpp"

#include <fmt/format.h>
#include <cmath>

namespace artemis {

Result<Isometry3d> isometryFromRt(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double orthonormality_tolerance) {
  if (!R.allFinite() || !t.allFinite()) return parseError("transform has non-finite entries");
  const double err = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > orthonormality_tolerance) {
    return parseError(fmt::format("rotation is not orthonormal (|R^T R - I| = {:.3g})", err));
  }
  if (R.determinant() <= 0.0) return parseError("rotation has a negative determinant (a reflection)");
  Isometry3d T = Isometry3d::Identity();
  // Re-orthonormalise so that products of many poses stay rigid.
  const Eigen::Quaterniond q(R);
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

Result<Isometry3d> isometryFromRowMajor3x4(std::span<const double> values, double orthonormality_tolerance) {
  if (values.size() != 12) {
    return parseError(fmt::format("a pose needs 12 numbers, got {}", values.size()));
  }
  const Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> pose(values.data());
  return isometryFromRt(pose.leftCols<3>(), pose.col(3), orthonormality_tolerance);
}

std::array<double, 12> toRowMajor3x4(const Isometry3d& T) {
  std::array<double, 12> out{};
  Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(out.data()) = T.matrix().topRows<3>();
  return out;
}

std::string formatRowMajor3x4(const Isometry3d& T) {
  const auto v = toRowMajor3x4(T);
  return fmt::format("{:.9e}", fmt::join(v, " "));
}

double rotationAngleDeg(const Isometry3d& T) {
  return Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI;
}

}  // namespace artemis
