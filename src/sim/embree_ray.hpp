#pragma once
// One Embree 3 ray with no hit yet, for the simulator's two casters (the static street and the
// movers). Included only by the .cpp files that already use Embree.

#include <embree3/rtcore.h>

#include <Eigen/Core>

namespace artemis::sim::detail {

inline RTCRayHit emptyRayHit(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                             float t_far) {
  RTCRayHit rh{};
  rh.ray.org_x = origin.x();
  rh.ray.org_y = origin.y();
  rh.ray.org_z = origin.z();
  rh.ray.dir_x = direction.x();
  rh.ray.dir_y = direction.y();
  rh.ray.dir_z = direction.z();
  rh.ray.tnear = t_near;
  rh.ray.tfar = t_far;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace artemis::sim::detail
