#include "artemis/render/ray_caster.hpp"

#include <embree3/rtcore.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "artemis/core/embree_ray.hpp"

namespace artemis::render {

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<std::uint32_t> face_of_primitive;  // Embree primitive id -> mesh face
  std::vector<Eigen::Vector3f> normal_of_primitive;
};

namespace {

bool usable(const MeshArrays& mesh, const std::array<std::uint32_t, 3>& tri) {
  for (const std::uint32_t v : tri) {
    if (v >= mesh.positions.size() || !mesh.positions[v].allFinite()) return false;
  }
  return true;
}

Eigen::Vector3f unitNormal(const MeshArrays& mesh, const std::array<std::uint32_t, 3>& tri) {
  const Eigen::Vector3f& a = mesh.positions[tri[0]];
  const Eigen::Vector3f n = (mesh.positions[tri[1]] - a).cross(mesh.positions[tri[2]] - a);
  const float length = n.norm();
  return length > 0.0F ? Eigen::Vector3f(n / length) : Eigen::Vector3f::Zero();
}

}  // namespace

RayCaster::RayCaster(const MeshArrays& mesh) : impl_(std::make_unique<Impl>()) {
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    if (!usable(mesh, mesh.triangles[f])) continue;
    impl_->face_of_primitive.push_back(static_cast<std::uint32_t>(f));
    impl_->normal_of_primitive.push_back(unitNormal(mesh, mesh.triangles[f]));
  }
  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  if (!impl_->face_of_primitive.empty()) {
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.positions.size()));
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      // Non-finite vertices belong to no face in the scene; zero keeps Embree's bounds finite.
      const Eigen::Vector3f p = mesh.positions[i].allFinite() ? mesh.positions[i] : Eigen::Vector3f::Zero();
      for (int k = 0; k < 3; ++k) vertices[3 * i + static_cast<std::size_t>(k)] = p[k];
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), impl_->face_of_primitive.size()));
    for (std::size_t i = 0; i < impl_->face_of_primitive.size(); ++i) {
      const auto& tri = mesh.triangles[impl_->face_of_primitive[i]];
      for (std::size_t k = 0; k < 3; ++k) indices[3 * i + k] = tri[k];
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl_->scene);
  if (const RTCError error = rtcGetDeviceError(impl_->device); error != RTC_ERROR_NONE) {
    throw std::runtime_error("Embree: building the scene failed with error " + std::to_string(static_cast<int>(error)));
  }
}

RayCaster::~RayCaster() {
  if (impl_->scene != nullptr) rtcReleaseScene(impl_->scene);
  if (impl_->device != nullptr) rtcReleaseDevice(impl_->device);
}

std::size_t RayCaster::faces() const {
  return impl_->face_of_primitive.size();
}

RayHit RayCaster::intersect(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& direction_W, float t_near,
                            float t_far) const {
  RayHit hit;
  if (impl_->face_of_primitive.empty() || !origin_W.allFinite() || !direction_W.allFinite()) return hit;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = embree::emptyRayHit(origin_W, direction_W, t_near, t_far);
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.t = rh.ray.tfar;
  hit.face = impl_->face_of_primitive[rh.hit.primID];
  hit.normal_W = impl_->normal_of_primitive[rh.hit.primID];
  return hit;
}

}  // namespace artemis::render
