#include "artemis/core/projection.hpp"

namespace artemis {

ProjectedPoints projectIntoCamera(const PointCloud& points_L, const CameraView& view) {
  ProjectedPoints out;
  const Eigen::Isometry3d T_C_L = view.T_L_C.inverse();
  const Eigen::Matrix3f R = T_C_L.linear().cast<float>();
  const Eigen::Vector3f t = T_C_L.translation().cast<float>();
  for (std::size_t i = 0; i < points_L.size(); ++i) {
    const Eigen::Vector3d p_C = (R * points_L.points[i] + t).cast<double>();
    const auto uv = view.camera.project(p_C);
    if (!uv || !view.camera.inImage(*uv)) continue;
    out.index.push_back(static_cast<std::uint32_t>(i));
    out.uv_px.push_back(uv->cast<float>());
    out.depth_m.push_back(static_cast<float>(p_C.z()));
  }
  return out;
}

}  // namespace artemis
