#include "mover_caster.hpp"

#include <embree3/rtcore.h>

#include <cstring>
#include <stdexcept>
#include <string>

#include "artemis/core/embree_ray.hpp"

namespace artemis::sim::detail {

struct MoverCaster::Impl {
  RTCDevice device = nullptr;
  std::vector<RTCScene> shapes;
};

namespace {

void check(RTCDevice device, const char* what) {
  if (const RTCError error = rtcGetDeviceError(device); error != RTC_ERROR_NONE) {
    throw std::runtime_error(std::string("Embree: ") + what + " failed with error " +
                             std::to_string(static_cast<int>(error)));
  }
}

RTCScene buildShape(RTCDevice device, const SceneMesh& mesh) {
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    std::memcpy(vertices + 3 * i, mesh.vertices[i].data(), 3 * sizeof(float));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    std::memcpy(indices + 3 * i, mesh.triangles[i].data(), 3 * sizeof(unsigned));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  check(device, "building a mover's shape");
  return scene;
}

}  // namespace

MoverCaster::MoverCaster(const std::vector<Mover>& movers) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  for (const Mover& m : movers) impl_->shapes.push_back(buildShape(impl_->device, m.shape.mesh));
}

MoverCaster::~MoverCaster() {
  for (RTCScene s : impl_->shapes) rtcReleaseScene(s);
  if (impl_->device != nullptr) rtcReleaseDevice(impl_->device);
}

std::unique_ptr<MoverCaster::Moment> MoverCaster::at(const std::vector<Eigen::Isometry3d>& T_S_M) const {
  if (T_S_M.size() != impl_->shapes.size()) {
    throw std::invalid_argument("MoverCaster::at: " + std::to_string(T_S_M.size()) + " poses for " +
                                std::to_string(impl_->shapes.size()) + " movers");
  }
  RTCScene scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  for (std::size_t i = 0; i < T_S_M.size(); ++i) {
    RTCGeometry instance = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, impl_->shapes[i]);
    rtcSetGeometryTimeStepCount(instance, 1);
    const Eigen::Matrix<float, 3, 4> xfm = T_S_M[i].matrix().topRows<3>().cast<float>();  // column-major
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm.data());
    rtcCommitGeometry(instance);
    rtcAttachGeometryByID(scene, instance, static_cast<unsigned>(i));
    rtcReleaseGeometry(instance);
  }
  rtcCommitScene(scene);
  check(impl_->device, "placing the movers");
  return std::unique_ptr<Moment>(new Moment(scene));
}

MoverCaster::Moment::~Moment() {
  rtcReleaseScene(static_cast<RTCScene>(scene_));
}

MoverHit MoverCaster::Moment::intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                                        float t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = embree::emptyRayHit(origin, direction, t_near, t_far);
  rtcIntersect1(static_cast<RTCScene>(scene_), &context, &rh);
  MoverHit hit;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
    hit.t = rh.ray.tfar;
    hit.mover = rh.hit.instID[0];
    hit.face = rh.hit.primID;
  }
  return hit;
}

bool MoverCaster::Moment::occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                                   float t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = origin.x();
  ray.org_y = origin.y();
  ray.org_z = origin.z();
  ray.dir_x = direction.x();
  ray.dir_y = direction.y();
  ray.dir_z = direction.z();
  ray.tnear = t_near;
  ray.tfar = t_far;
  ray.mask = 0xFFFFFFFFu;
  rtcOccluded1(static_cast<RTCScene>(scene_), &context, &ray);
  return ray.tfar < 0.0f;
}

}  // namespace artemis::sim::detail
