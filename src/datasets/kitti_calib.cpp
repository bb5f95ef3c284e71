#include "artemis/datasets/kitti_calib.hpp"

#include <fmt/format.h>

#include <cmath>

namespace artemis::datasets {

Result<CameraView> cameraFromProjection(const std::string& name, std::span<const double> P_rowmajor_3x4,
                                        const Isometry3d& T_R0_L, int width_px, int height_px) {
  if (P_rowmajor_3x4.size() != 12) {
    return parseError(fmt::format("{}: projection matrix needs 12 numbers", name));
  }
  const Eigen::Matrix<double, 3, 4> P =
      Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(P_rowmajor_3x4.data());
  const Eigen::Matrix3d K = P.leftCols<3>();
  const double fx = K(0, 0);
  const double fy = K(1, 1);
  const double tol = 1e-6 * std::max(1.0, std::abs(fx));
  if (!(fx > 0.0) || !(fy > 0.0) || std::abs(K(1, 0)) > tol || std::abs(K(2, 0)) > tol || std::abs(K(2, 1)) > tol ||
      std::abs(K(2, 2) - 1.0) > 1e-9) {
    return parseError(fmt::format("{}: projection matrix is not of the form K [I | t] with fx, fy > 0", name));
  }
  if (width_px <= 0 || height_px <= 0) {
    return parseError(fmt::format("{}: bad image size {}x{}", name, width_px, height_px));
  }
  CameraView view;
  view.name = name;
  view.camera.width_px = width_px;
  view.camera.height_px = height_px;
  view.camera.fx_px = fx;
  view.camera.fy_px = fy;
  view.camera.cx_px = K(0, 2);
  view.camera.cy_px = K(1, 2);
  // A skew term (K(0,1)) would be dropped by the pinhole model: refuse it rather than mis-project.
  if (std::abs(K(0, 1)) > tol) return parseError(fmt::format("{}: skewed projection matrix", name));
  Isometry3d T_C_R0 = Isometry3d::Identity();
  T_C_R0.translation() = K.inverse() * P.col(3);
  view.T_L_C = (T_C_R0 * T_R0_L).inverse();
  return view;
}

}  // namespace artemis::datasets
