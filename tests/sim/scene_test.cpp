// The procedural street: what it holds, that every face is tagged and textured, determinism, and
// the settings file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>
#include <map>
#include <set>

#include "artemis/sim/params.hpp"
#include "artemis/sim/scene.hpp"
#include "sim_fixture.hpp"

namespace artemis::sim {
namespace {

using test::defaultSim;

std::size_t countKind(const Scene& scene, const std::string& kind) {
  std::size_t n = 0;
  for (const auto& o : scene.objects) n += o.kind == kind ? 1 : 0;
  return n;
}

TEST(SimScene, HoldsTheObjectsAndClassesAStreetNeeds) {
  const Scene& scene = defaultSim().scene();
  EXPECT_GE(scene.length_m, 200.0);
  EXPECT_GE(countKind(scene, "car"), 10u);
  EXPECT_GE(countKind(scene, "person"), 4u);
  EXPECT_GE(countKind(scene, "tree"), 6u);
  EXPECT_GE(countKind(scene, "building"), 4u);
  EXPECT_GE(countKind(scene, "truck"), 1u);
  EXPECT_GE(countKind(scene, "bicycle"), 1u);
  EXPECT_GE(countKind(scene, "bench"), 1u);
  std::set<std::uint16_t> classes(scene.mesh.face_class.begin(), scene.mesh.face_class.end());
  for (std::uint16_t c :
       {cls::kRoad, cls::kParking, cls::kSidewalk, cls::kBuilding, cls::kFence, cls::kPole, cls::kTrafficSign,
        cls::kVegetation, cls::kTrunk, cls::kTerrain, cls::kCar, cls::kTruck, cls::kPerson, cls::kBicycle}) {
    EXPECT_TRUE(classes.count(c)) << "no face of class " << className(c);
  }
  EXPECT_FALSE(classes.count(cls::kUnlabeled));
}

TEST(SimScene, EveryFaceIsTaggedWithItsObject) {
  const Scene& scene = defaultSim().scene();
  const SceneMesh& m = scene.mesh;
  ASSERT_EQ(m.face_class.size(), m.faceCount());
  ASSERT_EQ(m.face_instance.size(), m.faceCount());
  ASSERT_EQ(m.face_object.size(), m.faceCount());
  std::set<std::uint16_t> instances;
  for (const auto& o : scene.objects) EXPECT_TRUE(instances.insert(o.instance_id).second) << "duplicate instance";
  EXPECT_FALSE(instances.count(0));
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    ASSERT_LT(m.face_object[f], scene.objects.size());
    ASSERT_EQ(m.face_instance[f], scene.objects[m.face_object[f]].instance_id) << "face " << f;
    for (std::uint32_t v : m.triangles[f]) ASSERT_LT(v, m.vertices.size());
  }
}

// Nothing stands where the simulated car drives: no vertex of another object lies inside KITTI's
// car body (4.8 m x 1.82 m, from 0.3 m above the road to its 1.52 m roof) at any pose of a
// 200-frame drive. Mapping drops returns found there (the vehicle's path is free space).
TEST(SimScene, NothingStandsInTheCarsPath) {
  sim::SimParams params;
  params.frames = 200;
  const Simulator sim(params);
  const Scene& scene = sim.scene();
  const Eigen::AlignedBox3d body(Eigen::Vector3d(-2.9, -0.91, 0.3 - 1.73), Eigen::Vector3d(1.9, 0.91, 1.52 - 1.73));
  std::vector<bool> object_vertex(scene.mesh.vertices.size(), false);
  for (std::size_t f = 0; f < scene.mesh.faceCount(); ++f) {
    const std::string& kind = scene.objects[scene.mesh.face_object[f]].kind;
    if (kind == "road" || kind == "parking" || kind == "ground") continue;
    for (const std::uint32_t v : scene.mesh.triangles[f]) object_vertex[v] = true;
  }
  std::size_t inside = 0;
  double nearest = 1e9;
  for (int frame = 0; frame < sim.frames(); ++frame) {
    const Isometry3d T_L_S = sim.T_S_L(frame).inverse();
    for (std::size_t v = 0; v < scene.mesh.vertices.size(); ++v) {
      if (!object_vertex[v]) continue;
      const Eigen::Vector3d p_L = T_L_S * scene.mesh.vertices[v].cast<double>();
      if (p_L.x() < body.min().x() || p_L.x() > body.max().x() || p_L.z() < body.min().z() || p_L.z() > body.max().z()) {
        continue;
      }
      nearest = std::min(nearest, std::abs(p_L.y()));
      inside += body.contains(p_L) ? 1 : 0;
    }
  }
  EXPECT_EQ(inside, 0u);
  EXPECT_GT(nearest, 0.91);  // beside the body, at its height: the closest a parked truck comes
  EXPECT_LT(nearest, 1.5);   // and it does come close
}

TEST(SimScene, CarsTouchTheCurbAndEachOtherPeopleStandTogether) {
  const Scene& scene = defaultSim().scene();
  const SceneParams& p = scene.params;
  const double curb_y = p.lane_width_m + p.parking_width_m;
  std::vector<const SceneObject*> cars;
  for (const auto& o : scene.objects) {
    if (o.kind == "car") cars.push_back(&o);
  }
  int at_curb = 0;
  int touching = 0;
  for (const auto* a : cars) {
    if (std::abs(std::abs(a->position_S.y()) + a->size_m.y() / 2 - curb_y) < 1e-9) ++at_curb;
    for (const auto* b : cars) {
      const bool same_side = (a->position_S.y() > 0) == (b->position_S.y() > 0);
      if (a != b && same_side &&
          std::abs(b->position_S.x() - a->position_S.x() - (a->size_m.x() + b->size_m.x()) / 2) < 1e-9) {
        ++touching;
      }
    }
  }
  EXPECT_GE(at_curb, 2);
  // On the mesh: those cars' tyres reach the curb's face.
  const SceneMesh& m = scene.mesh;
  int tyres_at_curb = 0;
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    if (m.face_material[f] != Material::kRubber || m.face_class[f] != cls::kCar) continue;
    for (std::uint32_t v : m.triangles[f]) {
      if (std::abs(std::abs(static_cast<double>(m.vertices[v].y())) - curb_y) < 1e-4 &&
          m.vertices[v].z() < p.curb_height_m) {
        ++tyres_at_curb;
        break;
      }
    }
  }
  EXPECT_GE(tyres_at_curb, 2);
  EXPECT_GE(touching, 1);
  int pairs = 0;
  for (const auto& a : scene.objects) {
    for (const auto& b : scene.objects) {
      if (&a < &b && a.kind == "person" && b.kind == "person" && (a.position_S - b.position_S).norm() < 1.0) ++pairs;
    }
  }
  EXPECT_GE(pairs, 1);
}

// Every surface has texture: its albedo varies over its faces, and lane markings are bright.
TEST(SimScene, SurfacesAreTexturedNotFlat) {
  const Scene& scene = defaultSim().scene();
  const SceneMesh& m = scene.mesh;
  std::map<Material, std::vector<double>> luminance;
  for (std::size_t f = 0; f < m.faceCount(); f += 7) {
    const auto& t = m.triangles[f];
    for (const Eigen::Vector3d& w : {Eigen::Vector3d(0.6, 0.3, 0.1), Eigen::Vector3d(0.2, 0.2, 0.6)}) {
      const Eigen::Vector3d p = w.x() * m.vertices[t[0]].cast<double>() + w.y() * m.vertices[t[1]].cast<double>() +
                                w.z() * m.vertices[t[2]].cast<double>();
      const Eigen::Vector3f a = scene.albedo(f, p);
      ASSERT_TRUE(a.minCoeff() >= 0.0f && a.maxCoeff() <= 1.0f);
      luminance[m.face_material[f]].push_back(0.2126 * a.x() + 0.7152 * a.y() + 0.0722 * a.z());
    }
  }
  for (const auto& [material, values] : luminance) {
    if (material == Material::kRubber) continue;  // tyres are plain black
    double mean = 0;
    for (double v : values) mean += v;
    mean /= static_cast<double>(values.size());
    double var = 0;
    for (double v : values) var += (v - mean) * (v - mean);
    const double sd = std::sqrt(var / static_cast<double>(values.size()));
    EXPECT_GT(sd, 0.01) << "material " << static_cast<int>(material) << " looks flat (" << values.size() << " samples)";
  }
  // The centre line is dashed paint; asphalt beside it is dark.
  const SceneObject& road = scene.objects.front();
  ASSERT_EQ(road.kind, "road");
  std::size_t road_face = 0;
  while (m.face_class[road_face] != cls::kRoad) ++road_face;
  EXPECT_GT(scene.albedo(road_face, {1.5, 0.0, 0.0}).x(), 0.5f);
  EXPECT_LT(scene.albedo(road_face, {1.5, 1.5, 0.0}).x(), 0.3f);
  EXPECT_LT(scene.albedo(road_face, {4.5, 0.0, 0.0}).x(), 0.3f);  // the gap between dashes
}

TEST(SimScene, SameSeedSameSceneOtherSeedOtherScene) {
  SceneParams p;
  const Scene a = generateScene(p, 0.0);
  const Scene b = generateScene(p, 0.0);
  ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
  EXPECT_TRUE(std::equal(a.mesh.vertices.begin(), a.mesh.vertices.end(), b.mesh.vertices.begin()));
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
  EXPECT_EQ(a.mesh.face_class, b.mesh.face_class);
  p.seed += 1;
  const Scene c = generateScene(p, 0.0);
  EXPECT_FALSE(c.mesh.vertices.size() == a.mesh.vertices.size() &&
               std::equal(a.mesh.vertices.begin(), a.mesh.vertices.end(), c.mesh.vertices.begin()));
}

TEST(SimScene, StreetGrowsToFitTheDrive) {
  SceneParams p;
  EXPECT_DOUBLE_EQ(generateScene(p, 100.0).length_m, p.street_length_m);
  EXPECT_DOUBLE_EQ(generateScene(p, 500.0).length_m, 500.0);
}

TEST(SimParams, JsonRoundTripAndErrors) {
  SimParams p;
  p.frames = 17;
  p.scene.seed = 123456789012345ull;
  p.lidar.range_noise_m = 0.035;
  p.camera.exposure_variation = 0.2;
  const std::string text = paramsToJson(p);
  auto back = paramsFromJson(text);
  ASSERT_TRUE(back) << back.status().toString();
  EXPECT_EQ(paramsToJson(*back), text);

  // A scene.json holds them under "params"; missing keys keep their defaults.
  auto nested = paramsFromJson(R"({"params": {"frames": 3, "lidar": {"dropout": 0.1}}})");
  ASSERT_TRUE(nested) << nested.status().toString();
  EXPECT_EQ(nested->frames, 3);
  EXPECT_DOUBLE_EQ(nested->lidar.dropout, 0.1);
  EXPECT_DOUBLE_EQ(nested->lidar.range_noise_m, LidarParams{}.range_noise_m);

  auto unknown = paramsFromJson(R"({"lidar": {"dropuot": 0.1}})");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.status().message().find("lidar.dropuot"), std::string::npos) << unknown.status().message();
  auto wrong_type = paramsFromJson(R"({"frames": "ten"})");
  ASSERT_FALSE(wrong_type);
  EXPECT_NE(wrong_type.status().message().find("frames"), std::string::npos);
  auto fractional = paramsFromJson(R"({"frames": 2.5})");
  EXPECT_FALSE(fractional);
  auto negative_seed = paramsFromJson(R"({"scene": {"seed": -1}})");
  EXPECT_FALSE(negative_seed);
  auto huge = paramsFromJson(R"({"frames": 4294967297})");  // would wrap to 1 as a 32-bit int
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.status().message().find("out of range"), std::string::npos) << huge.status().message();
  auto endless = paramsFromJson(R"({"frames": 100000, "trajectory": {"frame_rate_hz": 0.5}})");
  EXPECT_FALSE(endless);
  EXPECT_FALSE(paramsFromJson("{not json"));
  auto invalid = paramsFromJson(R"({"frames": 0})");
  ASSERT_FALSE(invalid);
  EXPECT_NE(invalid.status().message().find("frames"), std::string::npos);
}

TEST(SimParams, PresetsAndValidation) {
  auto demo = presetParams("demo");
  ASSERT_TRUE(demo);
  EXPECT_EQ(demo->frames, 30);
  EXPECT_EQ(presetParams("street")->frames, 100);
  EXPECT_FALSE(presetParams("city"));
  SimParams p;
  p.lidar.dropout = 1.0;
  EXPECT_FALSE(validate(p).isOk());
  p = SimParams{};
  p.trajectory.speed_amplitude_mps = 20.0;  // would stop and reverse
  EXPECT_FALSE(validate(p).isOk());
  EXPECT_TRUE(validate(SimParams{}).isOk());
}

}  // namespace
}  // namespace artemis::sim
