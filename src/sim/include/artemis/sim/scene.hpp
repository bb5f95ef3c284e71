#pragma once
// A procedural urban street: one triangle mesh whose every face carries a SemanticKITTI class id,
// an instance id and a material, plus the list of objects it was built from. Coordinates are the
// scene frame S: x along the street, y to the left, z up, road surface at z = 0.
//
// Instance ids are unique per object over the whole scene (1, 2, ...), stuff (road, buildings)
// included, so that the instance image separates every object.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "artemis/sim/params.hpp"

namespace artemis::sim {

// SemanticKITTI raw class ids used by the street.
namespace cls {
inline constexpr std::uint16_t kUnlabeled = 0;
inline constexpr std::uint16_t kCar = 10;
inline constexpr std::uint16_t kBicycle = 11;
inline constexpr std::uint16_t kTruck = 18;
inline constexpr std::uint16_t kPerson = 30;
inline constexpr std::uint16_t kBicyclist = 31;  // a bicycle with its rider (movers only)
inline constexpr std::uint16_t kRoad = 40;
inline constexpr std::uint16_t kParking = 44;
inline constexpr std::uint16_t kSidewalk = 48;
inline constexpr std::uint16_t kBuilding = 50;
inline constexpr std::uint16_t kFence = 51;
inline constexpr std::uint16_t kVegetation = 70;
inline constexpr std::uint16_t kTrunk = 71;
inline constexpr std::uint16_t kTerrain = 72;
inline constexpr std::uint16_t kPole = 80;
inline constexpr std::uint16_t kTrafficSign = 81;
inline constexpr std::uint16_t kOtherObject = 99;  // benches
// Moving objects, in LiDAR labels only (traffic.hpp); the camera's class image shows the plain class.
inline constexpr std::uint16_t kMovingCar = 252;
inline constexpr std::uint16_t kMovingBicyclist = 253;
inline constexpr std::uint16_t kMovingPerson = 254;
}  // namespace cls

// What a surface looks like: its procedural albedo texture and LiDAR reflectivity.
enum class Material : std::uint8_t {
  kAsphalt,   // road: grain, patches, lane markings
  kParking,   // parking lane: asphalt with bay lines
  kPaving,    // sidewalk tiles
  kCurb,      // concrete
  kGrass,     // verge and ground behind the buildings
  kBrick,     // facade: bricks, windows, doors
  kPlaster,   // facade: plaster, windows, doors
  kRoof,      // roofs
  kLeaves,    // tree crowns, bushes
  kBark,      // trunks
  kMetal,     // poles, bicycle frames
  kSign,      // traffic-sign plates
  kCarBody,   // paint
  kCarCabin,  // paint with windows
  kRubber,    // tyres
  kCloth,     // people: clothes, with a skin-coloured head
  kWood,      // fences, benches
  kCount
};

struct SceneObject {
  std::string kind;                          // "road", "building", "car", "tree", ...
  std::uint16_t class_id = cls::kUnlabeled;  // main class (a tree is vegetation with a trunk)
  std::uint16_t instance_id = 0;
  Eigen::Vector3d position_S = Eigen::Vector3d::Zero();  // object frame origin, on the ground
  double yaw_rad = 0.0;                                  // object frame x axis, from the street's x
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();      // extent along the object's x, y, z
  Eigen::Vector3f color = Eigen::Vector3f::Ones();       // base albedo (linear RGB)
  int variant = 0;                                       // shape or pattern variant

  // Points from the scene frame into the object frame.
  [[nodiscard]] Eigen::Vector3d toObject(const Eigen::Vector3d& p_S) const;
};

struct SceneMesh {
  std::vector<Eigen::Vector3f> vertices;  // scene frame
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint16_t> face_class;
  std::vector<std::uint16_t> face_instance;
  std::vector<Material> face_material;
  std::vector<std::uint32_t> face_object;  // index into Scene::objects

  [[nodiscard]] std::size_t faceCount() const { return triangles.size(); }
  [[nodiscard]] Eigen::Vector3d faceNormal(std::size_t face) const;  // unit, outward
};

struct Scene {
  SceneParams params;
  double length_m = 0.0;  // the street runs over x in [0, length_m]
  SceneMesh mesh;
  std::vector<SceneObject> objects;

  // Albedo (linear RGB, 0..1) of face `face` at point p_S on it: procedural solid textures in the
  // object's frame, so a facade's bricks and windows stay put however the facade is triangulated.
  [[nodiscard]] Eigen::Vector3f albedo(std::size_t face, const Eigen::Vector3d& p_S) const;
  // LiDAR return strength, 0..1, of face `face` at p_S hit at incidence cosine `cos_incidence`.
  [[nodiscard]] float reflectivity(std::size_t face, const Eigen::Vector3d& p_S, double cos_incidence) const;
};

// The street for `params`, long enough for `min_length_m`. Deterministic: the same params give the
// same scene, vertex for vertex.
Scene generateScene(const SceneParams& params, double min_length_m);

// Per class id: how many objects have faces of that class (a traffic sign's post counts as a pole,
// a tree counts as vegetation and as trunk) and how many faces; the table `artemis sim` prints.
struct ClassCount {
  std::uint16_t class_id = 0;
  std::size_t objects = 0;
  std::size_t triangles = 0;
};
std::vector<ClassCount> countClasses(const Scene& scene);

// Name of a class id used by the street ("car", "traffic-sign", ...).
const char* className(std::uint16_t class_id);
// SemanticKITTI's display colour (RGB) of a class id used by the street; black for 0 (sky).
std::array<std::uint8_t, 3> classColor(std::uint16_t class_id);

}  // namespace artemis::sim
