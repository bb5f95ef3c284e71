#include "artemis/sim/simulator.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "colour.hpp"
#include "ego_path.hpp"
#include "mover_caster.hpp"
#include "noise.hpp"
#include "raycaster.hpp"
#include "rosette.hpp"

namespace artemis::sim {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::Vector3f;

const KittiCalibration& kittiCalibration() {
  // calib_cam_to_cam.txt and calib_velo_to_cam.txt of KITTI's 2011_09_26 drives.
  static const KittiCalibration calibration = [] {
    KittiCalibration c{};
    c.P0 = {7.215377e+02, 0, 6.095593e+02, 0, 0, 7.215377e+02, 1.728540e+02, 0, 0, 0, 1, 0};
    c.P1 = {7.215377e+02, 0, 6.095593e+02, -3.875744e+02, 0, 7.215377e+02, 1.728540e+02, 0, 0, 0, 1, 0};
    c.P2 = {7.215377e+02, 0, 6.095593e+02, 4.485728e+01, 0, 7.215377e+02, 1.728540e+02, 2.163791e-01, 0, 0, 1,
            2.745884e-03};
    c.P3 = {7.215377e+02, 0, 6.095593e+02, -3.395242e+02, 0, 7.215377e+02, 1.728540e+02, 2.199936e+00, 0, 0, 1,
            2.729905e-03};
    Matrix3d R_velo;
    R_velo << 7.533745e-03, -9.999714e-01, -6.166020e-04, 1.480249e-02, 7.280733e-04, -9.998902e-01, 9.998621e-01,
        7.523790e-03, 1.480755e-02;
    const Vector3d t_velo(-4.069766e-03, -7.631618e-02, -2.717806e-01);
    Matrix3d R_rect;
    R_rect << 9.999239e-01, 9.837760e-03, -7.445048e-03, -9.869795e-03, 9.999421e-01, -4.278459e-03, 7.402527e-03,
        4.351614e-03, 9.999631e-01;
    const Matrix3d R = R_rect * R_velo;
    const Vector3d t = R_rect * t_velo;
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) c.Tr[static_cast<std::size_t>(4 * r + k)] = R(r, k);
      c.Tr[static_cast<std::size_t>(4 * r + 3)] = t(r);
    }
    return c;
  }();
  return calibration;
}

// The static street's BVH, and the movers' (when there is traffic), cast against together: a
// ray takes the nearer of the two hits.
struct Simulator::Tracer {
  explicit Tracer(const SceneMesh& mesh, const std::vector<Mover>& movers) : raycaster(mesh) {
    if (!movers.empty()) mover_caster = std::make_unique<detail::MoverCaster>(movers);
  }
  detail::Raycaster raycaster;
  std::unique_ptr<detail::MoverCaster> mover_caster;
};

namespace {

// What a ray hit: a face of the static street or of a mover, the mover's pose, and the hit point
// in the frame its textures live in (the scene's, or the mover's own).
struct Surface {
  bool on_mover = false;
  std::uint32_t face = 0;
  float t = 0.0f;
  const Mover* mover = nullptr;
  Isometry3d T_S_M = Isometry3d::Identity();
};

}  // namespace

// The frame's movers and their poses, null without traffic.
struct detail::MoversAt {
  std::unique_ptr<detail::MoverCaster::Moment> moment;
  std::vector<Isometry3d> T_S_M;
};

namespace {

using detail::MoversAt;

// Nearest hit of the static street and the movers along origin + t d_S, t in [t_near, t_far].
std::optional<Surface> castRay(const detail::Raycaster& street, const std::vector<Mover>& movers, const MoversAt& at,
                               const Vector3f& origin, const Vector3f& d_S, float t_near, float t_far) {
  const detail::Hit hit = street.intersect(origin, d_S, t_near, t_far);
  if (at.moment) {
    const detail::MoverHit m = at.moment->intersect(origin, d_S, t_near, hit.valid() ? hit.t : t_far);
    if (m.valid()) return Surface{true, m.face, m.t, &movers[m.mover], at.T_S_M[m.mover]};
  }
  if (!hit.valid()) return std::nullopt;
  return Surface{false, hit.face, hit.t, nullptr, Isometry3d::Identity()};
}

MoversAt placeMovers(const detail::MoverCaster* caster, std::vector<Isometry3d> T_S_M) {
  MoversAt at;
  if (caster == nullptr) return at;
  at.moment = caster->at(T_S_M);
  at.T_S_M = std::move(T_S_M);
  return at;
}

}  // namespace

Simulator::Simulator(const SimParams& params) : params_(params) {
  if (Status s = validate(params_); !s.isOk()) throw std::invalid_argument(s.message());
  const double end_x =
      params_.trajectory.start_x_m + detail::egoDistanceAt(params_.trajectory, stamp_s(params_.frames - 1));
  scene_ = generateScene(params_.scene, end_x + params_.trajectory.start_x_m);
  scene_.mesh.vertices.reserve(scene_.mesh.vertices.size() + 1);  // so that the ray caster shares them
  movers_ = planTraffic(params_, scene_);
  tracer_ = std::make_unique<Tracer>(scene_.mesh, movers_);

  const KittiCalibration& c = kittiCalibration();
  camera_.width_px = params_.camera.width_px;
  camera_.height_px = params_.camera.height_px;
  camera_.fx_px = c.P2[0];
  camera_.fy_px = c.P2[5];
  camera_.cx_px = c.P2[2];
  camera_.cy_px = c.P2[6];
  // P2 = K [I | t]: camera 2 sits at K^-1 P2[:, 3] in the rectified camera-0 frame.
  const Vector3d Kt(c.P2[3], c.P2[7], c.P2[11]);
  const Vector3d t_C2_R0 = camera_.K().inverse() * Kt;
  Isometry3d T_C2_R0 = Isometry3d::Identity();
  T_C2_R0.translation() = t_C2_R0;
  const Isometry3d T_R0_L = isometryFromRowMajor3x4(c.Tr).value();
  T_L_C_ = (T_C2_R0 * T_R0_L).inverse();
  T_S_W_ = T_S_L(0);
}

Simulator::~Simulator() = default;

double Simulator::stamp_s(int frame) const {
  return frame / params_.trajectory.frame_rate_hz;
}

double Simulator::speed_mps(int frame) const {
  const TrajectoryParams& p = params_.trajectory;
  return p.speed_mean_mps +
         p.speed_amplitude_mps * std::sin(2.0 * std::numbers::pi * stamp_s(frame) / p.speed_period_s);
}

std::vector<Isometry3d> Simulator::moverPoses(int frame) const {
  std::vector<Isometry3d> poses;
  poses.reserve(movers_.size());
  for (const Mover& m : movers_) poses.push_back(moverPose(m, params_, scene_.length_m, stamp_s(frame)));
  return poses;
}

Isometry3d Simulator::T_S_L(int frame) const {
  return T_S_L_at(stamp_s(frame));
}

Isometry3d Simulator::T_S_L_at(double t_s) const {
  const detail::PlanarPose pose = detail::egoPoseAtDistance(params_, detail::egoDistanceAt(params_.trajectory, t_s));
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(pose.yaw, Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Vector3d(pose.x, pose.y, params_.lidar.mount_height_m);
  return T;
}

Isometry3d Simulator::T_W_L(int frame) const {
  if (frame == 0) return Isometry3d::Identity();  // exactly, not up to rounding
  return T_S_W_.inverse() * T_S_L(frame);
}

namespace {

std::vector<double> beamElevations(const LidarParams& p) {
  std::vector<double> elevation(static_cast<std::size_t>(2 * p.beams_per_block));
  for (int b = 0; b < p.beams_per_block; ++b) {
    const double f = p.beams_per_block > 1 ? static_cast<double>(b) / (p.beams_per_block - 1) : 0.0;
    elevation[static_cast<std::size_t>(b)] =
        (p.upper_top_deg + f * (p.upper_bottom_deg - p.upper_top_deg)) * std::numbers::pi / 180.0;
    elevation[static_cast<std::size_t>(b + p.beams_per_block)] =
        (p.lower_top_deg + f * (p.lower_bottom_deg - p.lower_top_deg)) * std::numbers::pi / 180.0;
  }
  return elevation;
}

}  // namespace

// One beam's return: the point in the LiDAR's frame (x y z, intensity), its label and face.
struct Simulator::LidarReturn {
  Eigen::Vector4f point;
  std::uint32_t label = 0;
  std::uint32_t face = LidarScan::kNoFace;
};

std::optional<Simulator::LidarReturn> Simulator::traceBeam(const Isometry3d& T_S_L, const Vector3d& d_L,
                                                           std::uint64_t ray_seed,
                                                           const detail::MoversAt& movers) const {
  const LidarParams& p = params_.lidar;
  if (detail::unit(ray_seed) < p.dropout) return std::nullopt;
  const Vector3f origin = T_S_L.translation().cast<float>();
  const Vector3d d_S = T_S_L.linear() * d_L;
  const std::optional<Surface> hit = castRay(tracer_->raycaster, movers_, movers, origin, d_S.cast<float>(),
                                             static_cast<float>(p.min_range_m), static_cast<float>(p.max_range_m));
  if (!hit) return std::nullopt;
  const double range_m = hit->t + p.range_noise_m * detail::gaussian(detail::mix64(ray_seed));
  if (range_m < p.min_range_m || range_m > p.max_range_m) return std::nullopt;
  const Vector3d p_S = origin.cast<double>() + static_cast<double>(hit->t) * d_S;
  LidarReturn out;
  float intensity = 0.0f;
  if (hit->on_mover) {
    const Scene& shape = hit->mover->shape;
    const Matrix3d R_S_M = hit->T_S_M.linear();
    const double cos_incidence = shape.mesh.faceNormal(hit->face).dot(R_S_M.transpose() * d_S);
    intensity = shape.reflectivity(hit->face, hit->T_S_M.inverse() * p_S, cos_incidence);
    out.label =
        static_cast<std::uint32_t>(hit->mover->moving_id) | (static_cast<std::uint32_t>(hit->mover->instance_id) << 16);
  } else {
    const double cos_incidence = scene_.mesh.faceNormal(hit->face).dot(d_S);
    intensity = scene_.reflectivity(hit->face, p_S, cos_incidence);
    out.face = hit->face;
    out.label = static_cast<std::uint32_t>(scene_.mesh.face_class[hit->face]) |
                (static_cast<std::uint32_t>(scene_.mesh.face_instance[hit->face]) << 16);
  }
  const Vector3f p_L = (range_m * d_L).cast<float>();
  out.point = Eigen::Vector4f(p_L.x(), p_L.y(), p_L.z(), intensity);
  return out;
}

namespace {

// The returns in slot order (the slots that returned nothing left out), with their times if given.
LidarScan gatherReturns(std::vector<std::optional<Simulator::LidarReturn>>& slots, const std::vector<float>& times) {
  LidarScan out;
  out.points_L.reserve(slots.size() / 2);
  for (std::size_t i = 0; i < slots.size(); ++i) {
    if (!slots[i]) continue;
    out.points_L.push_back(slots[i]->point);
    out.faces.push_back(slots[i]->face);
    out.labels.push_back(slots[i]->label);
    if (!times.empty()) out.time_s.push_back(times[i]);
  }
  return out;
}

}  // namespace

LidarScan Simulator::scan(int frame) const {
  const LidarParams& p = params_.lidar;
  const std::uint64_t frame_seed = detail::hash(params_.scene.seed, 0x11DA7u, static_cast<std::uint64_t>(frame));
  const MoversAt movers = placeMovers(tracer_->mover_caster.get(), moverPoses(frame));
  if (p.rosette_points_per_s > 0.0) {
    // The rosette's beams over the frame's period, each from the pose at its own time: the scan
    // carries the rig's motion during it, as a real one does, and each point's time.
    const double t0 = stamp_s(frame);
    const std::vector<detail::RosetteBeam> beams = detail::rosetteBeams(p, t0, 1.0 / params_.trajectory.frame_rate_hz);
    std::vector<std::optional<LidarReturn>> slots(beams.size());
    std::vector<float> times(beams.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, beams.size(), 512), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        slots[i] = traceBeam(T_S_L_at(t0 + beams[i].time_s), beams[i].d_L, detail::hash(frame_seed, i), movers);
        times[i] = static_cast<float>(beams[i].time_s);
      }
    });
    return gatherReturns(slots, times);
  }
  const int columns = static_cast<int>(std::lround(360.0 / p.azimuth_step_deg));
  const int beams = 2 * p.beams_per_block;
  const std::vector<double> elevation = beamElevations(p);
  const Isometry3d T = T_S_L(frame);
  // Every ray has its slot, so the output order (column by column, top beam first) is fixed.
  const std::size_t n = static_cast<std::size_t>(columns) * static_cast<std::size_t>(beams);
  std::vector<std::optional<LidarReturn>> slots(n);
  tbb::parallel_for(tbb::blocked_range<int>(0, columns, 64), [&](const tbb::blocked_range<int>& range) {
    for (int c = range.begin(); c < range.end(); ++c) {
      const double azimuth = -std::numbers::pi + (c + 0.5) * p.azimuth_step_deg * std::numbers::pi / 180.0;
      for (int b = 0; b < beams; ++b) {
        const std::size_t slot =
            static_cast<std::size_t>(c) * static_cast<std::size_t>(beams) + static_cast<std::size_t>(b);
        const double e = elevation[static_cast<std::size_t>(b)];
        const Vector3d d_L(std::cos(e) * std::cos(azimuth), std::cos(e) * std::sin(azimuth), std::sin(e));
        slots[slot] = traceBeam(T, d_L, detail::hash(frame_seed, slot), movers);
      }
    }
  });
  return gatherReturns(slots, {});
}

CameraImages Simulator::render(int frame) const {
  const CameraParams& p = params_.camera;
  const int w = camera_.width_px;
  const int h = camera_.height_px;
  CameraImages out{ImageU8(w, h, 3), ImageU16(w, h, 1), ImageU16(w, h, 1), ImageU16(w, h, 1)};

  const Isometry3d T_S_C = T_S_L(frame) * T_L_C_;
  const Matrix3d R = T_S_C.linear();
  const Vector3f origin = T_S_C.translation().cast<float>();
  const double sun_az = p.sun_azimuth_deg * std::numbers::pi / 180.0;
  const double sun_el = p.sun_elevation_deg * std::numbers::pi / 180.0;
  const Vector3d sun(std::cos(sun_el) * std::cos(sun_az), std::cos(sun_el) * std::sin(sun_az), std::sin(sun_el));
  const std::uint64_t frame_seed = detail::hash(params_.scene.seed, 0xCA3E7u, static_cast<std::uint64_t>(frame));
  // Exposure differs from frame to frame, as an auto-exposure camera's does.
  const double exposure = 1.5 * (1.0 + p.exposure_variation * (2.0 * detail::unit(frame_seed) - 1.0));
  const Vector3d sun_colour(1.0, 0.95, 0.85);
  const Vector3d sky_light(0.8, 0.88, 1.0);
  const MoversAt movers = placeMovers(tracer_->mover_caster.get(), moverPoses(frame));
  const auto in_shadow = [&](const Vector3f& from) {
    return tracer_->raycaster.occluded(from, sun.cast<float>(), 0.0f, 1e4f) ||
           (movers.moment && movers.moment->occluded(from, sun.cast<float>(), 0.0f, 1e4f));
  };

  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      for (int u = 0; u < w; ++u) {
        const Vector3d d_C((u - camera_.cx_px) / camera_.fx_px, (v - camera_.cy_px) / camera_.fy_px, 1.0);
        const Vector3d d_S = R * d_C;  // z component 1 in C: hit.t is the depth along the optical axis
        const std::optional<Surface> hit =
            castRay(tracer_->raycaster, movers_, movers, origin, d_S.cast<float>(), 0.05f, 1e4f);
        Vector3d linear;
        if (hit) {
          const Vector3d p_S = origin.cast<double>() + static_cast<double>(hit->t) * d_S;
          Vector3d n;
          Vector3d albedo;
          if (hit->on_mover) {
            n = hit->T_S_M.linear() * hit->mover->shape.mesh.faceNormal(hit->face);
            albedo = hit->mover->shape.albedo(hit->face, hit->T_S_M.inverse() * p_S).cast<double>();
            out.semantic.at(u, v) = hit->mover->class_id;
            out.instance.at(u, v) = hit->mover->instance_id;
          } else {
            n = scene_.mesh.faceNormal(hit->face);
            albedo = scene_.albedo(hit->face, p_S).cast<double>();
            out.semantic.at(u, v) = scene_.mesh.face_class[hit->face];
            out.instance.at(u, v) = scene_.mesh.face_instance[hit->face];
          }
          if (n.dot(d_S) > 0.0) n = -n;  // light the side the camera sees
          double direct = std::max(0.0, n.dot(sun));
          if (direct > 0.0 && in_shadow((p_S + 0.01 * n).cast<float>())) direct = 0.0;
          const double sky_view = 0.75 + 0.25 * n.z();  // surfaces facing up see more sky
          linear =
              albedo.cwiseProduct(p.ambient * sky_view * sky_light + (1.0 - p.ambient) * 1.6 * direct * sun_colour);
          const double depth_mm = std::round(static_cast<double>(hit->t) * 1000.0);
          out.depth_mm.at(u, v) = depth_mm <= 65535.0 ? static_cast<std::uint16_t>(depth_mm) : 0;
        } else {
          const double up = std::clamp(d_S.normalized().z(), 0.0, 1.0);
          linear = Vector3d(0.55, 0.68, 0.85) * (1.0 - up) + Vector3d(0.25, 0.42, 0.75) * up;
        }
        const auto pixel =
            static_cast<std::uint64_t>(v) * static_cast<std::uint64_t>(w) + static_cast<std::uint64_t>(u);
        for (int c = 0; c < 3; ++c) {
          const double noise =
              p.noise_sigma * detail::gaussian(detail::hash(frame_seed, pixel, static_cast<std::uint64_t>(c)));
          const double value = 255.0 * detail::srgbEncode(exposure * linear(c)) + noise;
          out.rgb.at(u, v, c) = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
        }
      }
    }
  });
  return out;
}

}  // namespace artemis::sim
