// Choosing the movers: followers in the ego lane, oncoming cars, cyclists by the far kerb, people
// crossing ahead of the ego car and people pacing the sidewalks, in that order, each drawn from one
// seeded generator and kept only if it stays clear of the ego car, the static obstacles (parked
// vehicles, furniture, standing people) and the movers placed before it.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "artemis/sim/traffic.hpp"
#include "ego_path.hpp"
#include "noise.hpp"
#include "traffic_shapes.hpp"

namespace artemis::sim {

using Eigen::Isometry3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

struct Footprint {
  Isometry3d T_S = Isometry3d::Identity();
  Vector2d half = Vector2d::Zero();
};

Footprint box(double x0, double x1, double y0, double y1) {
  Footprint f;
  f.T_S.translation() = Vector3d((x0 + x1) / 2, (y0 + y1) / 2, 0.0);
  f.half = {std::abs(x1 - x0) / 2, std::abs(y1 - y0) / 2};
  return f;
}

// What stands still where movers could go: parked vehicles, street furniture, standing people.
std::vector<Footprint> obstacles(const Scene& street) {
  std::vector<Footprint> out;
  for (const SceneObject& o : street.objects) {
    Vector2d half;
    if (o.kind == "car" || o.kind == "truck") {
      half = o.size_m.head<2>() / 2;
    } else if (o.kind == "person") {
      half = {0.15, 0.3};
    } else if (o.kind == "pole") {
      half = {0.12, 0.12};
    } else if (o.kind == "traffic-sign") {
      half = {0.35, 0.35};  // the plate, beside its post
    } else if (o.kind == "bench" || o.kind == "bicycle") {
      half = o.size_m.head<2>() / 2;
    } else {
      continue;
    }
    Footprint f;
    f.T_S.linear() = Eigen::AngleAxisd(o.yaw_rad, Vector3d::UnitZ()).toRotationMatrix();
    f.T_S.translation() = Vector3d(o.position_S.x(), o.position_S.y(), 0.0);
    f.half = half;
    out.push_back(f);
  }
  return out;
}

class Planner {
 public:
  Planner(const SimParams& params, const Scene& street)
      : p_(params),
        t_(params.traffic),
        street_(street),
        rng_(detail::hash(params.scene.seed, 0x7A4F1Cu)),
        obstacles_(obstacles(street)),
        duration_s_((params.frames - 1) / params.trajectory.frame_rate_hz),
        step_s_(std::min(0.05, 0.5 / params.trajectory.frame_rate_hz)),
        curb_y_(params.scene.lane_width_m + params.scene.parking_width_m) {}

  std::vector<Mover> plan() {
    followers();
    lineOfMovers("car", t_.oncoming_cars_per_100m, p_.scene.lane_width_m / 2 - 0.07, -t_.oncoming_speed_mps);
    lineOfMovers("cyclist", t_.cyclists_per_100m, p_.scene.lane_width_m - 0.53, -t_.cyclist_speed_mps);
    for (int i = 0; i < t_.crossings; ++i) crossing();
    walkers();
    return std::move(movers_);
  }

 private:
  Mover make(const std::string& kind) {
    Mover m;
    m.kind = kind;
    const std::size_t id = street_.objects.size() + movers_.size() + 1;
    if (id > 0xFFFFu) throw std::length_error("sim: more than 65535 objects and movers; instance ids are 16-bit");
    m.instance_id = static_cast<std::uint16_t>(id);
    if (kind == "car") {
      m.class_id = cls::kCar;
      m.moving_id = cls::kMovingCar;
      detail::buildCarShape(m, p_.scene, rng_);
    } else if (kind == "cyclist") {
      m.class_id = cls::kBicyclist;
      m.moving_id = cls::kMovingBicyclist;
      detail::buildCyclistShape(m, p_.scene, rng_);
    } else {
      m.class_id = cls::kPerson;
      m.moving_id = cls::kMovingPerson;
      detail::buildWalkerShape(m, p_.scene, rng_);
    }
    return m;
  }

  [[nodiscard]] Isometry3d egoAt(double t) const {
    const detail::PlanarPose e = detail::egoPoseAtDistance(p_, detail::egoDistanceAt(p_.trajectory, t));
    Isometry3d T = Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(e.yaw, Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Vector3d(e.x, e.y, 0.0);
    return T;
  }

  // Whether `m` stays clear of the ego car and of `others` over [t0, t1].
  [[nodiscard]] bool clearOver(const Mover& m, double t0, double t1, double ego_margin_m, double margin_m) const {
    const Vector2d ego_half(kEgoHalfLength_m, kEgoHalfWidth_m);
    for (double t = std::max(0.0, t0); t <= std::min(t1, duration_s_) + 1e-9; t += step_s_) {
      const Isometry3d T = moverPose(m, p_, street_.length_m, t);
      if (footprintsOverlap(T, m.half_extent_m, egoAt(t), ego_half, ego_margin_m)) return false;
      for (const Mover& o : movers_) {
        if (o.motion.kind == MotionKind::kPace) continue;  // on the sidewalks, apart (walkers())
        if (footprintsOverlap(T, m.half_extent_m, moverPose(o, p_, street_.length_m, t), o.half_extent_m, margin_m))
          return false;
      }
    }
    return true;
  }

  [[nodiscard]] bool clearOfObstacles(const Footprint& f, double margin_m) const {
    return std::none_of(obstacles_.begin(), obstacles_.end(), [&](const Footprint& o) {
      return footprintsOverlap(f.T_S, f.half, o.T_S, o.half, margin_m);
    });
  }

  void followers() {
    for (int side : {1, -1}) {
      const int n = side > 0 ? t_.cars_ahead : t_.cars_behind;
      for (int i = 0; i < n; ++i) {
        Mover m = make("car");
        m.motion.kind = MotionKind::kFollow;
        m.motion.gap_m = side * ((side > 0 ? t_.gap_ahead_m : t_.gap_behind_m) + i * t_.follower_spacing_m);
        m.motion.gap_variation_m = t_.gap_variation_m;
        m.motion.gap_period_s = t_.gap_period_s * rng_.uniform(0.8, 1.25);
        m.motion.phase_rad = rng_.uniform(0.0, 2.0 * std::numbers::pi);
        movers_.push_back(std::move(m));
      }
    }
  }

  // `density` per 100 m of movers along the line y at one speed, wrapping around the street's ends:
  // evenly spread with some jitter, they never close up. The lane must be free of the ego car's
  // weave and of parked vehicles reaching into it, or none are placed.
  void lineOfMovers(const std::string& kind, double per_100m, double y, double speed_mps) {
    const int n = static_cast<int>(std::round(per_100m * street_.length_m / 100.0));
    if (n <= 0) return;
    const double spacing = street_.length_m / n;
    const double jitter = std::clamp((spacing - 7.0) / 2.0, 0.0, 0.25 * spacing);
    // The ego lane (and its followers) reaches this far left.
    const double ego_top = -p_.scene.lane_width_m / 2 + std::abs(p_.trajectory.lateral_amplitude_m) + kEgoHalfWidth_m;
    for (int i = 0; i < n; ++i) {
      Mover m = make(kind);
      m.motion.kind = MotionKind::kLine;
      m.motion.x0 = (i + 0.5) * spacing + rng_.uniform(-jitter, jitter);
      m.motion.y0 = y;
      m.motion.speed_mps = speed_mps;
      const double lo = y - m.half_extent_m.y();
      const double hi = y + m.half_extent_m.y();
      const bool meets_other_line = std::any_of(bands_.begin(), bands_.end(), [&](const Band& b) {
        return b.kind != kind && lo < b.hi && b.lo < hi;
      });
      if (lo < ego_top + 0.05 || meets_other_line || !clearOfObstacles(box(0.0, street_.length_m, lo, hi), 0.0)) {
        continue;
      }
      bands_.push_back({kind, lo, hi});
      movers_.push_back(std::move(m));
    }
  }

  // Lateral stretch of the road one line of movers sweeps.
  struct Band {
    std::string kind;
    double lo = 0.0;
    double hi = 0.0;
  };
  std::vector<Band> bands_;

  // A person who waits on one sidewalk and crosses the street ahead of the ego car, in a gap of the
  // traffic (none found in 300 draws: no crossing).
  // Whether crossing `m` is on the road at some frame while 8-60 m ahead of the ego car (in view).
  [[nodiscard]] bool crossesInView(const Mover& m) const {
    const double frame_s = 1.0 / p_.trajectory.frame_rate_hz;
    for (double t = 0.0; t <= duration_s_ + 1e-9; t += frame_s) {
      const Eigen::Vector3d c = moverPose(m, p_, street_.length_m, t).translation();
      const double ahead = c.x() - egoAt(t).translation().x();
      if (std::abs(c.y()) < p_.scene.lane_width_m && ahead > 8.0 && ahead < 60.0) return true;
    }
    return false;
  }

  // The first 300 draws must cross in view of the camera, the next 300 anywhere.
  void crossing() {
    Mover m = make("person");
    for (int attempt = 0; attempt < 600; ++attempt) {
      // Under way when the drive starts, or starting later; anywhere from behind the ego car to far
      // ahead of it: the traffic decides where it can cross.
      const double t0 = rng_.uniform(-8.0, std::max(0.0, duration_s_ - 2.0));
      const double x = egoAt(std::max(0.0, t0)).translation().x() + rng_.uniform(-20.0, 110.0);
      const int side = rng_.chance(0.5) ? 1 : -1;
      const double y_out = curb_y_ + rng_.uniform(0.6, p_.scene.sidewalk_width_m - 0.6);
      if (x < 5.0 || x > street_.length_m - 5.0) continue;
      m.motion.kind = MotionKind::kCross;
      m.motion.x0 = x;
      m.motion.y0 = side * y_out;
      m.motion.y1 = -side * y_out;
      m.motion.z = p_.scene.curb_height_m;
      m.motion.kerb_y_m = curb_y_;
      m.motion.speed_mps = t_.walker_speed_mps * rng_.uniform(0.85, 1.15);
      m.motion.t0_s = t0;
      const double walk_s = 2.0 * y_out / m.motion.speed_mps;
      if (!clearOfObstacles(box(x - 0.2, x + 0.2, -y_out - 0.3, y_out + 0.3), 0.1) ||
          (attempt < 300 && !crossesInView(m)) || !clearOver(m, t0 - 0.5, t0 + walk_s + 0.5, 1.0, 0.5)) {
        continue;
      }
      crossing_x_.push_back(x);
      movers_.push_back(std::move(m));
      return;
    }
  }

  // People pacing to and fro over free stretches of the sidewalks, apart from each other.
  void walkers() {
    const int n = static_cast<int>(std::round(t_.walkers_per_100m * street_.length_m / 100.0));
    std::vector<Footprint> taken;
    for (int i = 0; i < n; ++i) {
      Mover m = make("person");
      for (int attempt = 0; attempt < 100; ++attempt) {
        const int side = rng_.chance(0.5) ? 1 : -1;
        const double y = side * (curb_y_ + rng_.uniform(0.6, p_.scene.sidewalk_width_m - 0.6));
        const double len = rng_.uniform(8.0, 25.0);
        const double x0 = rng_.uniform(5.0, street_.length_m - 5.0 - len);
        const bool forward = rng_.chance(0.5);
        const Footprint path = box(x0 - 0.4, x0 + len + 0.4, y - 0.4, y + 0.4);
        const auto meets = [&](const Footprint& f) {
          return footprintsOverlap(path.T_S, path.half, f.T_S, f.half, 0.2);
        };
        if (!clearOfObstacles(path, 0.1) || std::any_of(taken.begin(), taken.end(), meets) ||
            std::any_of(crossing_x_.begin(), crossing_x_.end(),
                        [&](double x) { return x > x0 - 1.5 && x < x0 + len + 1.5; })) {
          continue;
        }
        m.motion.kind = MotionKind::kPace;
        m.motion.x0 = forward ? x0 : x0 + len;
        m.motion.x1 = forward ? x0 + len : x0;
        m.motion.y0 = y;
        m.motion.z = p_.scene.curb_height_m;
        m.motion.speed_mps = t_.walker_speed_mps * rng_.uniform(0.8, 1.2);
        m.motion.t0_s = rng_.uniform(0.0, 2.0 * len / m.motion.speed_mps);
        taken.push_back(path);
        movers_.push_back(std::move(m));
        break;
      }
    }
  }

  const SimParams& p_;
  const TrafficParams& t_;
  const Scene& street_;
  detail::Rng rng_;
  std::vector<Footprint> obstacles_;
  double duration_s_;
  double step_s_;
  double curb_y_;
  std::vector<Mover> movers_;
  std::vector<double> crossing_x_;
};

}  // namespace

std::vector<Mover> planTraffic(const SimParams& params, const Scene& street) {
  if (!params.traffic.any()) return {};
  return Planner(params, street).plan();
}

}  // namespace artemis::sim
