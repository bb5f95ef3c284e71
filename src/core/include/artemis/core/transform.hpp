#pragma once
// Rigid transforms. Naming: T_A_B maps points from frame B into frame A (p_A = T_A_B * p_B).
// On disk a pose is 12 numbers, the row-major top 3x4 of the 4x4 matrix (KITTI's convention).

#include <Eigen/Geometry>
#include <array>
#include <span>
#include <string>

#include "artemis/core/status.hpp"

namespace artemis {

using Isometry3d = Eigen::Isometry3d;

// Builds a transform from 12 row-major numbers [R | t]. The rotation part is checked:
// |R^T R - I| must be below `orthonormality_tolerance`, det(R) > 0.
Result<Isometry3d> isometryFromRowMajor3x4(std::span<const double> values, double orthonormality_tolerance = 1e-3);

// Same check on a full 3x3 rotation and a translation.
Result<Isometry3d> isometryFromRt(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                                  double orthonormality_tolerance = 1e-3);

// 12 numbers, row-major top 3x4.
std::array<double, 12> toRowMajor3x4(const Isometry3d& T);

// "r00 r01 r02 t0 r10 ... t2" with enough digits to round-trip doubles.
std::string formatRowMajor3x4(const Isometry3d& T);

// Angle of the rotation part, in degrees.
double rotationAngleDeg(const Isometry3d& T);

}  // namespace artemis
