#pragma once
// Cameras from KITTI's rectified projection matrices.

#include <span>
#include <string>

#include "artemis/core/frame.hpp"
#include "artemis/core/status.hpp"

namespace artemis::datasets {

// A rectified KITTI camera i has P_rect_i = K [I | t_i] in the rectified camera-0 frame, so
// p_image ~ P_rect_i * T_R0_L * p_L. This returns the pinhole camera K and T_L_C with
// T_C_L = [I | K^-1 P[:,3]] * T_R0_L. Fails when P is not of that form (a malformed calibration).
Result<CameraView> cameraFromProjection(const std::string& name, std::span<const double> P_rowmajor_3x4,
                                        const Isometry3d& T_R0_L, int width_px, int height_px);

}  // namespace artemis::datasets
