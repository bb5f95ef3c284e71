#pragma once
// One Embree 3 ray with no hit yet, for every caster that builds one (the simulator's static street
// and movers, render's RayCaster). Header-only, and included only by .cpp files of modules that
// link Embree: core itself does not.

#include <embree3/rtcore.h>

#include <Eigen/Core>

namespace artemis::embree {

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

}  // namespace artemis::embree
