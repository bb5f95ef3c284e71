// Moving traffic: movers show in the LiDAR (moving labels, where they are) and the camera (their
// class, occluding what lies behind), never in the static ground truth, never on the ego car.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <tbb/task_arena.h>

#include "artemis/datasets/semantic_kitti.hpp"
#include "artemis/sim/simulator.hpp"
#include "artemis/sim/traffic.hpp"

namespace artemis::sim {
namespace {

SimParams trafficParams(const std::string& traffic, int frames) {
  SimParams p;
  p.frames = frames;
  p.traffic = trafficPreset(traffic).value();
  return p;
}

const Simulator& drive0013() {
  static const Simulator s(trafficParams("drive0013", 60));
  return s;
}

const Simulator& streetTraffic() {
  static const Simulator s(trafficParams("street", 100));
  return s;
}

// Whether p_S lies inside mover footprint T_S_M grown by margin_m (shrunk when negative).
bool inside(const Isometry3d& T_S_M, const Mover& m, const Eigen::Vector3d& p_S, double margin_m) {
  const Eigen::Vector3d p_M = T_S_M.inverse() * p_S;
  return std::abs(p_M.x()) < m.half_extent_m.x() + margin_m && std::abs(p_M.y()) < m.half_extent_m.y() + margin_m;
}

TEST(SimTraffic, Drive0013HasOneCarAheadAndOneBehindInTheEgoLane) {
  const Simulator& sim = drive0013();
  ASSERT_EQ(sim.movers().size(), 2u);
  for (int frame : {0, 25, 59}) {
    const LidarScan scan = sim.scan(frame);
    const Isometry3d T_S_L = sim.T_S_L(frame);
    const std::vector<Isometry3d> T_S_M = sim.moverPoses(frame);
    for (std::size_t k = 0; k < 2; ++k) {
      const Mover& m = sim.movers()[k];
      EXPECT_EQ(m.moving_id, cls::kMovingCar);
      // Its centre in the LiDAR frame: in the lane, 10-20 m ahead (first) or behind (second).
      const Eigen::Vector3d c_L = T_S_L.inverse() * T_S_M[k].translation();
      const double ahead = k == 0 ? c_L.x() : -c_L.x();
      EXPECT_GT(ahead, 10.0) << "frame " << frame << " mover " << k;
      EXPECT_LT(ahead, 20.0) << "frame " << frame << " mover " << k;
      EXPECT_LT(std::abs(c_L.y()), 0.8) << "frame " << frame << " mover " << k;
      // Its returns: many, labelled moving-car with its instance, all on its body; no static
      // return inside its body.
      std::size_t on_car = 0;
      for (std::size_t i = 0; i < scan.points_L.size(); ++i) {
        const Eigen::Vector3d p_S = T_S_L * scan.points_L[i].head<3>().cast<double>();
        const std::uint32_t label = scan.labels[i];
        if ((label >> 16) == m.instance_id) {
          ++on_car;
          ASSERT_EQ(label & 0xFFFFu, cls::kMovingCar);
          ASSERT_TRUE(inside(T_S_M[k], m, p_S, 0.1)) << "frame " << frame << " point " << i;
          ASSERT_EQ(scan.faces[i], LidarScan::kNoFace);
        } else if (p_S.z() > 0.4 && p_S.z() < 1.3) {
          ASSERT_FALSE(inside(T_S_M[k], m, p_S, -0.1)) << "a static return inside the car, frame " << frame;
        }
      }
      EXPECT_GT(on_car, 300u) << "frame " << frame << " mover " << k;
    }
  }
}

TEST(SimTraffic, SameSettingsSameFramesOnAnyThreadCount) {
  const Simulator& a = drive0013();
  const Simulator b(a.params());  // planned again from the same seed
  LidarScan one;
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { one = b.scan(7); });
  const LidarScan many = a.scan(7);
  ASSERT_EQ(one.points_L.size(), many.points_L.size());
  EXPECT_EQ(one.labels, many.labels);
  for (std::size_t i = 0; i < one.points_L.size(); ++i) ASSERT_EQ(one.points_L[i], many.points_L[i]) << i;
}

TEST(SimTraffic, MovingLabelsReadAsTheirClassesAndCountAsMoving) {
  namespace sk = datasets::semantic_kitti;
  EXPECT_EQ(sk::toTrainId(cls::kMovingCar), sk::toTrainId(cls::kCar));
  EXPECT_EQ(sk::toTrainId(cls::kMovingPerson), sk::toTrainId(cls::kPerson));
  EXPECT_EQ(sk::toTrainId(cls::kMovingBicyclist), sk::toTrainId(cls::kBicyclist));
  EXPECT_TRUE(sk::find(cls::kMovingCar)->moving);
  EXPECT_FALSE(sk::find(cls::kBicyclist)->moving);
}

TEST(SimTraffic, CameraSeesTheCarAheadWhereTheStreetWasAndTheRestIsUntouched) {
  const Simulator& moving = drive0013();
  SimParams still_params = moving.params();
  still_params.traffic = TrafficParams{};
  const Simulator still(still_params);
  const CameraImages a = moving.render(10);
  const CameraImages b = still.render(10);
  const std::uint16_t ahead = moving.movers()[0].instance_id;
  std::size_t car_px = 0;
  std::size_t car_px_changed = 0;
  std::size_t same = 0;
  const std::size_t n = static_cast<std::size_t>(a.rgb.width()) * static_cast<std::size_t>(a.rgb.height());
  for (int v = 0; v < a.rgb.height(); ++v) {
    for (int u = 0; u < a.rgb.width(); ++u) {
      const bool changed =
          a.rgb.at(u, v, 0) != b.rgb.at(u, v, 0) || a.rgb.at(u, v, 1) != b.rgb.at(u, v, 1) ||
          a.rgb.at(u, v, 2) != b.rgb.at(u, v, 2);
      same += changed ? 0 : 1;
      if (a.instance.at(u, v) != ahead) continue;
      ++car_px;
      ASSERT_EQ(a.semantic.at(u, v), cls::kCar);  // a segmenter sees a car
      ASSERT_NE(b.instance.at(u, v), ahead);
      ASSERT_LT(a.depth_mm.at(u, v), b.depth_mm.at(u, v) == 0 ? 65535 : b.depth_mm.at(u, v));  // in front
      car_px_changed += changed ? 1 : 0;
    }
  }
  EXPECT_GT(car_px, 3000u);  // a car 10-20 m ahead covers a good part of the image
  EXPECT_GT(car_px_changed, car_px * 9 / 10);
  EXPECT_GT(same, n * 8 / 10);  // elsewhere the image stays as it was (bar the car's shadow)
}

TEST(SimTraffic, StreetMixHasCarsBothWaysCyclistsAndPeople) {
  const Simulator& sim = streetTraffic();
  std::map<std::string, int> kinds;
  std::map<MotionKind, int> motions;
  for (const Mover& m : sim.movers()) {
    ++kinds[m.kind];
    ++motions[m.motion.kind];
    EXPECT_GT(m.instance_id, sim.scene().objects.size());
  }
  EXPECT_EQ(motions[MotionKind::kFollow], 3);
  EXPECT_GE(kinds["car"], 6);
  EXPECT_GE(kinds["cyclist"], 2);
  EXPECT_GE(motions[MotionKind::kPace], 5);
  EXPECT_GE(motions[MotionKind::kCross], 1);
  // Someone crosses the road in view, 8-60 m ahead of the ego car.
  bool crossing_in_view = false;
  for (int frame = 0; frame < sim.frames() && !crossing_in_view; ++frame) {
    const std::vector<Isometry3d> T_S_M = sim.moverPoses(frame);
    for (std::size_t i = 0; i < T_S_M.size(); ++i) {
      const Eigen::Vector3d c_L = sim.T_S_L(frame).inverse() * T_S_M[i].translation();
      crossing_in_view |= sim.movers()[i].motion.kind == MotionKind::kCross && c_L.x() > 8.0 && c_L.x() < 60.0 &&
                          std::abs(T_S_M[i].translation().y()) < sim.params().scene.lane_width_m;
    }
  }
  EXPECT_TRUE(crossing_in_view);
  // Every moving label shows up in a scan.
  std::map<std::uint32_t, std::size_t> labels;
  for (int frame : {0, 50}) {
    for (std::uint32_t l : sim.scan(frame).labels) ++labels[l & 0xFFFFu];
  }
  EXPECT_GT(labels[cls::kMovingCar], 1000u);
  EXPECT_GT(labels[cls::kMovingBicyclist], 20u);
  EXPECT_GT(labels[cls::kMovingPerson], 50u);
}

// Sampled four times a frame: no mover overlaps the ego car, the follower cars or the crossing
// people overlap nothing, and walkers keep apart.
TEST(SimTraffic, MoversKeepClearOfTheEgoCarAndOfEachOther) {
  const Simulator& sim = streetTraffic();
  const SimParams& p = sim.params();
  const std::vector<Mover>& movers = sim.movers();
  const Eigen::Vector2d ego_half(kEgoHalfLength_m, kEgoHalfWidth_m);
  for (int k = 0; k < 4 * sim.frames(); ++k) {
    const double t = k / (4.0 * p.trajectory.frame_rate_hz);
    const Isometry3d T_S_L = [&] {
      const double s = t * p.trajectory.frame_rate_hz;  // T_S_L between frames: nearest frame is enough
      return sim.T_S_L(static_cast<int>(std::lround(s)) < sim.frames() ? static_cast<int>(std::lround(s))
                                                                        : sim.frames() - 1);
    }();
    std::vector<Isometry3d> T(movers.size());
    for (std::size_t i = 0; i < movers.size(); ++i) T[i] = moverPose(movers[i], p, sim.scene().length_m, t);
    for (std::size_t i = 0; i < movers.size(); ++i) {
      if (k % 4 == 0) {
        ASSERT_FALSE(footprintsOverlap(T[i], movers[i].half_extent_m, T_S_L, ego_half)) << "mover " << i << " t " << t;
      }
      for (std::size_t j = i + 1; j < movers.size(); ++j) {
        ASSERT_FALSE(footprintsOverlap(T[i], movers[i].half_extent_m, T[j], movers[j].half_extent_m))
            << movers[i].kind << " " << i << " meets " << movers[j].kind << " " << j << " at t " << t;
      }
    }
  }
}

TEST(SimTraffic, StaticGroundTruthHoldsNoMover) {
  const Simulator& sim = streetTraffic();
  const SceneMesh& mesh = sim.scene().mesh;
  for (int frame : {0, 40, 99}) {
    const std::vector<Isometry3d> T_S_M = sim.moverPoses(frame);
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
      const auto& t = mesh.triangles[f];
      const Eigen::Vector3d c =
          (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]).cast<double>() / 3.0;
      for (std::size_t i = 0; i < T_S_M.size(); ++i) {
        if (c.z() < T_S_M[i].translation().z() + 0.05 || c.z() > 2.0) continue;  // the ground under it
        ASSERT_FALSE(inside(T_S_M[i], sim.movers()[i], c, -0.05))
            << "face " << f << " (class " << mesh.face_class[f] << ") inside mover " << i << " at frame " << frame;
      }
    }
  }
}

TEST(SimTraffic, SettingsRoundTripAndAreChecked) {
  SimParams p;
  p.traffic = trafficPreset("street").value();
  p.traffic.walker_speed_mps = 1.1;
  const std::string text = paramsToJson(p);
  auto back = paramsFromJson(text);
  ASSERT_TRUE(back) << back.status().toString();
  EXPECT_EQ(paramsToJson(*back), text);
  EXPECT_EQ(back->traffic.cars_ahead, 2);
  EXPECT_DOUBLE_EQ(back->traffic.walker_speed_mps, 1.1);
  EXPECT_FALSE(SimParams{}.traffic.any());  // off unless asked for
  EXPECT_FALSE(trafficPreset("none")->any());
  EXPECT_FALSE(trafficPreset("rush-hour"));
  SimParams bad = p;
  bad.traffic.gap_ahead_m = 5.0;  // bumper to bumper with the ego car
  EXPECT_FALSE(validate(bad).isOk());
  bad = p;
  bad.traffic.cars_ahead = 4;  // the fourth would drive off the street's end
  EXPECT_FALSE(validate(bad).isOk());
  bad = p;
  bad.traffic.walkers_per_100m = -1.0;
  EXPECT_FALSE(validate(bad).isOk());
  EXPECT_FALSE(paramsFromJson(R"({"traffic": {"cars_ahaed": 1}})"));
}

TEST(SimTraffic, NoTrafficNoMovers) {
  SimParams p;
  p.frames = 2;
  const Simulator sim(p);
  EXPECT_TRUE(sim.movers().empty());
  for (std::uint32_t l : sim.scan(1).labels) ASSERT_LT(l & 0xFFFFu, 200u);
}

TEST(SimTraffic, FootprintOverlapAgreesWithPointSampling) {
  const auto pose = [](double x, double y, double yaw) {
    Isometry3d T = Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(x, y, 0);
    return T;
  };
  const Eigen::Vector2d a(2.0, 0.9);
  const Eigen::Vector2d b(0.3, 0.2);
  int checked = 0;
  for (double x = -3.0; x <= 3.0; x += 0.37) {
    for (double y = -2.0; y <= 2.0; y += 0.29) {
      for (double yaw : {0.0, 0.4, 1.2}) {
        const Isometry3d Ta = pose(0, 0, 0.3);
        const Isometry3d Tb = pose(x, y, yaw);
        bool sampled = false;  // any point of b (dense grid) inside a
        for (double u = -1; u <= 1 && !sampled; u += 0.05) {
          for (double w = -1; w <= 1 && !sampled; w += 0.05) {
            const Eigen::Vector3d q = Ta.inverse() * (Tb * Eigen::Vector3d(u * b.x(), w * b.y(), 0));
            sampled = std::abs(q.x()) <= a.x() && std::abs(q.y()) <= a.y();
          }
        }
        const bool exact = footprintsOverlap(Ta, a, Tb, b);
        if (sampled) {
          EXPECT_TRUE(exact) << x << " " << y << " " << yaw;
        }
        checked += sampled ? 1 : 0;
      }
    }
  }
  EXPECT_GT(checked, 20);
}

}  // namespace
}  // namespace artemis::sim
