// The street layout: ground strips, buildings, vegetation, street furniture, vehicles and people,
// placed from one seeded generator in a fixed order.

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "artemis/sim/scene.hpp"
#include "colour.hpp"
#include "mesh_builder.hpp"
#include "noise.hpp"
#include "shapes.hpp"

namespace artemis::sim {

using Eigen::Isometry3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector3f;

Vector3d SceneObject::toObject(const Vector3d& p_S) const {
  const Vector3d d = p_S - position_S;
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z()};
}

Vector3d SceneMesh::faceNormal(std::size_t face) const {
  const auto& t = triangles[face];
  const Vector3d a = vertices[t[0]].cast<double>();
  const Vector3d n = (vertices[t[1]].cast<double>() - a).cross(vertices[t[2]].cast<double>() - a);
  const double len = n.norm();
  return len > 0.0 ? Vector3d(n / len) : Vector3d::UnitZ();
}

const char* className(std::uint16_t class_id) {
  switch (class_id) {
    case cls::kUnlabeled: return "unlabeled";
    case cls::kCar: return "car";
    case cls::kBicycle: return "bicycle";
    case cls::kTruck: return "truck";
    case cls::kPerson: return "person";
    case cls::kBicyclist: return "bicyclist";
    case cls::kRoad: return "road";
    case cls::kParking: return "parking";
    case cls::kSidewalk: return "sidewalk";
    case cls::kBuilding: return "building";
    case cls::kFence: return "fence";
    case cls::kVegetation: return "vegetation";
    case cls::kTrunk: return "trunk";
    case cls::kTerrain: return "terrain";
    case cls::kPole: return "pole";
    case cls::kTrafficSign: return "traffic-sign";
    case cls::kOtherObject: return "other-object";
    case cls::kMovingCar: return "moving-car";
    case cls::kMovingBicyclist: return "moving-bicyclist";
    case cls::kMovingPerson: return "moving-person";
    default: return "?";
  }
}

std::array<std::uint8_t, 3> classColor(std::uint16_t class_id) {
  switch (class_id) {  // semantic-kitti.yaml's color_map, turned from BGR into RGB
    case cls::kCar: return {100, 150, 245};
    case cls::kBicycle: return {100, 230, 245};
    case cls::kTruck: return {80, 30, 180};
    case cls::kPerson: return {255, 30, 30};
    case cls::kBicyclist: return {255, 40, 200};
    case cls::kRoad: return {255, 0, 255};
    case cls::kParking: return {255, 150, 255};
    case cls::kSidewalk: return {75, 0, 75};
    case cls::kBuilding: return {255, 200, 0};
    case cls::kFence: return {255, 120, 50};
    case cls::kVegetation: return {0, 175, 0};
    case cls::kTrunk: return {135, 60, 0};
    case cls::kTerrain: return {150, 240, 80};
    case cls::kPole: return {255, 240, 150};
    case cls::kTrafficSign: return {255, 0, 0};
    case cls::kOtherObject: return {255, 255, 50};
    case cls::kMovingCar: return classColor(cls::kCar);
    case cls::kMovingBicyclist: return classColor(cls::kBicyclist);
    case cls::kMovingPerson: return classColor(cls::kPerson);
    default: return {0, 0, 0};
  }
}

std::vector<ClassCount> countClasses(const Scene& scene) {
  std::map<std::uint16_t, ClassCount> by_class;
  std::map<std::pair<std::uint16_t, std::uint16_t>, bool> seen;
  const SceneMesh& m = scene.mesh;
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    ClassCount& c = by_class[m.face_class[f]];
    c.class_id = m.face_class[f];
    ++c.triangles;
    if (!seen[{m.face_class[f], m.face_instance[f]}]) {
      seen[{m.face_class[f], m.face_instance[f]}] = true;
      ++c.objects;
    }
  }
  std::vector<ClassCount> out;
  for (const auto& [id, c] : by_class) out.push_back(c);
  return out;
}

namespace {

using detail::MeshBuilder;
using detail::Rng;

using detail::frameAt;

using detail::rgb;

// Occupied stretches of x along one side's strip, so that objects of one kind keep apart.
class Intervals {
 public:
  bool free(double x0, double x1) const {
    return std::none_of(taken_.begin(), taken_.end(), [&](const auto& t) { return x0 < t.second && t.first < x1; });
  }
  void take(double x0, double x1) { taken_.emplace_back(x0, x1); }

 private:
  std::vector<std::pair<double, double>> taken_;
};

class StreetBuilder {
 public:
  StreetBuilder(const SceneParams& params, double length_m)
      : p_(params), rng_(params.seed), builder_(scene_.mesh, params.max_edge_m) {
    scene_.params = params;
    scene_.length_m = length_m;
    road_half_ = p_.lane_width_m;
    curb_y_ = road_half_ + p_.parking_width_m;
    verge_y_ = curb_y_ + p_.sidewalk_width_m;
    building_y_ = verge_y_ + p_.verge_width_m;
  }

  Scene build() {
    ground();
    buildings();
    trees();
    bushes();
    fences();
    poles();
    signs();
    vehicles();
    people();
    bicycles();
    return std::move(scene_);
  }

 private:
  double count(double per_100m, int at_least) const {
    return std::max(static_cast<double>(at_least), std::round(per_100m * scene_.length_m / 100.0));
  }

  std::uint32_t addObject(const std::string& kind, std::uint16_t class_id, const Vector3d& position, double yaw,
                          const Vector3d& size, const Vector3f& color, int variant, Material material) {
    if (scene_.objects.size() >= 0xFFFFu) {
      throw std::length_error("sim: more than 65535 objects; instance ids are 16-bit (shorten the street)");
    }
    SceneObject o;
    o.kind = kind;
    o.class_id = class_id;
    o.instance_id = static_cast<std::uint16_t>(scene_.objects.size() + 1);
    o.position_S = position;
    o.yaw_rad = yaw;
    o.size_m = size;
    o.color = color;
    o.variant = variant;
    scene_.objects.push_back(o);
    const auto index = static_cast<std::uint32_t>(scene_.objects.size() - 1);
    builder_.setTag(class_id, o.instance_id, material, index);
    builder_.setMaxEdge(p_.max_edge_m);
    return index;
  }

  // Side s = +1 (left, y > 0) or -1 (right); y measured outward from the street's centre line.
  static Vector3d at(double x, int side, double y_out, double z) { return {x, side * y_out, z}; }

  // A quad between y_out = a and b on one side at height z, facing up.
  void groundStrip(int side, double a, double b, double z) {
    const double L = scene_.length_m;
    if (side > 0) {
      builder_.quad(at(0, side, a, z), at(L, side, a, z), at(L, side, b, z), at(0, side, b, z));
    } else {
      builder_.quad(at(0, side, b, z), at(L, side, b, z), at(L, side, a, z), at(0, side, a, z));
    }
  }

  void ground() {
    const double L = scene_.length_m;
    const double h = p_.curb_height_m;
    addObject("road", cls::kRoad, {0, 0, 0}, 0, {L, 2 * road_half_, 0}, rgb(0.16, 0.16, 0.16), 0, Material::kAsphalt);
    builder_.quad({0, -road_half_, 0}, {L, -road_half_, 0}, {L, road_half_, 0}, {0, road_half_, 0});
    for (int side : {1, -1}) {
      addObject("parking", cls::kParking, at(0, side, road_half_, 0), 0, {L, p_.parking_width_m, 0}, rgb(0.2, 0.2, 0.2),
                0, Material::kParking);
      groundStrip(side, road_half_, curb_y_, 0.0);
      addObject("sidewalk", cls::kSidewalk, at(0, side, curb_y_, h), 0, {L, p_.sidewalk_width_m, h},
                rgb(0.45, 0.43, 0.40), 0, Material::kPaving);
      groundStrip(side, curb_y_, verge_y_, h);
      builder_.setMaterial(Material::kCurb);  // the curb's face belongs to the sidewalk
      if (side > 0) {
        builder_.quad(at(0, side, curb_y_, 0), at(L, side, curb_y_, 0), at(L, side, curb_y_, h),
                      at(0, side, curb_y_, h));
      } else {
        builder_.quad(at(L, side, curb_y_, 0), at(0, side, curb_y_, 0), at(0, side, curb_y_, h),
                      at(L, side, curb_y_, h));
      }
      addObject("terrain", cls::kTerrain, at(0, side, verge_y_, h), 0, {L, p_.verge_width_m + 30.0, 0},
                rgb(0.09, 0.2, 0.05), 0, Material::kGrass);
      groundStrip(side, verge_y_, building_y_ + 30.0, h);
    }
  }

  void buildings() {
    const Vector3f bricks[] = {rgb(0.42, 0.16, 0.10), rgb(0.50, 0.25, 0.15), rgb(0.35, 0.20, 0.16)};
    const Vector3f plasters[] = {rgb(0.75, 0.68, 0.55), rgb(0.62, 0.64, 0.66), rgb(0.78, 0.60, 0.45),
                                 rgb(0.55, 0.62, 0.50), rgb(0.80, 0.78, 0.72)};
    for (int side : {1, -1}) {
      double x = rng_.uniform(-6.0, 0.0);
      while (x < scene_.length_m) {
        const double width = rng_.uniform(12.0, 28.0);
        const double height = rng_.uniform(7.0, 18.0);
        const double depth = rng_.uniform(10.0, 16.0);
        const bool brick = rng_.chance(0.5);
        const Vector3f color = brick ? bricks[rng_.integer(0, 2)] : plasters[rng_.integer(0, 4)];
        const int bay_variant = rng_.integer(0, 2);
        // Object frame: origin at the facade's street-side corner with the smaller x, x along the
        // street, y away from it, z up from the sidewalk level.
        const double yaw = 0.0;
        const Vector3d origin = at(x, side, building_y_, p_.curb_height_m);
        addObject("building", cls::kBuilding, origin, yaw, {width, depth, height}, color, bay_variant,
                  brick ? Material::kBrick : Material::kPlaster);
        const Isometry3d T = frameAt(origin, yaw);
        const Vector3d lo = side > 0 ? Vector3d(0, 0, 0) : Vector3d(0, -depth, 0);
        const Vector3d hi = side > 0 ? Vector3d(width, depth, height) : Vector3d(width, 0, height);
        // Walls, then the roof in its own material.
        Vector3d b[4] = {T * Vector3d(lo.x(), lo.y(), 0), T * Vector3d(hi.x(), lo.y(), 0),
                         T * Vector3d(hi.x(), hi.y(), 0), T * Vector3d(lo.x(), hi.y(), 0)};
        for (int k = 0; k < 4; ++k) {
          const int n = (k + 1) % 4;
          builder_.quad(b[k], b[n], b[n] + Vector3d(0, 0, height), b[k] + Vector3d(0, 0, height));
        }
        builder_.setMaterial(Material::kRoof);
        builder_.quad(b[0] + Vector3d(0, 0, height), b[1] + Vector3d(0, 0, height), b[2] + Vector3d(0, 0, height),
                      b[3] + Vector3d(0, 0, height));
        x += width + (rng_.chance(0.4) ? rng_.uniform(4.0, 10.0) : 0.0);
      }
    }
  }

  // Places `n` items of length `len` along one side's strip [x margin], apart from what is taken.
  template <typename Place>
  void scatter(int n, double len, double spacing, Intervals* taken_left, Intervals* taken_right, Place&& place,
               int side_only = 0) {
    int placed = 0;
    for (int attempt = 0; attempt < 200 * n && placed < n; ++attempt) {
      const int side = side_only != 0 ? side_only : (rng_.chance(0.5) ? 1 : -1);
      const double x = rng_.uniform(3.0, scene_.length_m - 3.0 - len);
      Intervals* taken = side > 0 ? taken_left : taken_right;
      if (!taken->free(x - spacing, x + len + spacing)) continue;
      taken->take(x, x + len);
      place(x, side);
      ++placed;
    }
  }

  void trees() {
    const int n = static_cast<int>(count(p_.trees_per_100m, 6));
    const Vector3f tints[] = {rgb(0.07, 0.17, 0.04), rgb(0.09, 0.19, 0.05), rgb(0.14, 0.18, 0.05)};
    scatter(n, 0.0, 6.0, &verge_left_, &verge_right_, [&](double x, int side) {
      const double trunk_r = rng_.uniform(0.15, 0.25);
      const double trunk_h = rng_.uniform(2.4, 3.2);
      const double crown_r = rng_.uniform(1.6, 2.2);
      const double crown_rz = crown_r * rng_.uniform(1.0, 1.25);
      const Vector3d base = at(x, side, verge_y_ + 1.5, p_.curb_height_m);
      addObject("tree", cls::kVegetation, base, 0.0, {2 * crown_r, 2 * crown_r, trunk_h + 1.8 * crown_rz},
                tints[rng_.integer(0, 2)], 0, Material::kBark);
      builder_.setClass(cls::kTrunk);
      builder_.setMaxEdge(0.25);
      builder_.cylinder(frameAt(base, 0.0), trunk_r, 0.0, trunk_h);
      builder_.setClass(cls::kVegetation);
      builder_.setMaterial(Material::kLeaves);
      builder_.setMaxEdge(0.4);
      builder_.ellipsoid(frameAt(base + Vector3d(0, 0, trunk_h + 0.8 * crown_rz), rng_.uniform(0, 3.14)),
                         {crown_r, crown_r * rng_.uniform(0.85, 1.0), crown_rz});
    });
  }

  void bushes() {
    const int n = static_cast<int>(count(p_.bushes_per_100m, 2));
    scatter(n, 0.0, 2.5, &verge_left_, &verge_right_, [&](double x, int side) {
      const double r = rng_.uniform(0.6, 0.95);
      const double rz = rng_.uniform(0.5, 0.8);
      const Vector3d centre =
          at(x, side, verge_y_ + rng_.uniform(1.2, p_.verge_width_m - 1.1), p_.curb_height_m + 0.6 * rz);
      addObject("bush", cls::kVegetation, centre, 0.0, {2 * r, 2 * r, 1.6 * rz}, rgb(0.08, 0.18, 0.05), 1,
                Material::kLeaves);
      builder_.setMaxEdge(0.3);
      builder_.ellipsoid(frameAt(centre, rng_.uniform(0, 3.14)), {r, r * 0.9, rz});
    });
  }

  void fences() {
    const int n = static_cast<int>(count(p_.fences_per_100m, 1));
    for (int i = 0, attempt = 0; i < n && attempt < 100; ++attempt) {
      const int side = rng_.chance(0.5) ? 1 : -1;
      const double len = rng_.uniform(6.0, 15.0);
      const double x = rng_.uniform(3.0, scene_.length_m - 3.0 - len);
      Intervals& edge = side > 0 ? fence_left_ : fence_right_;
      if (!edge.free(x - 2.0, x + len + 2.0)) continue;
      edge.take(x, x + len);
      const double height = rng_.uniform(1.0, 1.4);
      const Vector3d origin = at(x, side, verge_y_ + 0.15, p_.curb_height_m);
      addObject("fence", cls::kFence, origin, 0.0, {len, 0.05, height}, rgb(0.32, 0.2, 0.1), 0, Material::kWood);
      builder_.box(frameAt(origin, 0.0), {0, -0.025, 0}, {len, 0.025, height});
      ++i;
    }
  }

  void poles() {
    const int n = static_cast<int>(count(p_.poles_per_100m, 2));
    scatter(n, 0.3, 8.0, &curbside_left_, &curbside_right_, [&](double x, int side) {
      const double height = rng_.uniform(5.5, 7.0);
      const Vector3d base = at(x + 0.15, side, curb_y_ + 0.5, p_.curb_height_m);
      addObject("pole", cls::kPole, base, 0.0, {0.2, 1.5, height}, rgb(0.33, 0.34, 0.35), 0, Material::kMetal);
      builder_.setMaxEdge(0.5);
      builder_.cylinder(frameAt(base, 0.0), 0.09, 0.0, height);
      // The lamp's arm reaches over the road.
      const Isometry3d T = frameAt(base, side > 0 ? -std::numbers::pi / 2 : std::numbers::pi / 2);
      builder_.box(T, {0.0, -0.04, height - 0.12}, {1.4, 0.04, height - 0.04}, true);
      builder_.box(T, {1.1, -0.15, height - 0.28}, {1.6, 0.15, height - 0.12}, true);
    });
  }

  void signs() {
    const int n = static_cast<int>(count(p_.signs_per_100m, 2));
    const Vector3f faces[] = {rgb(0.6, 0.05, 0.04), rgb(0.05, 0.15, 0.55), rgb(0.75, 0.6, 0.05)};
    scatter(n, 0.3, 5.0, &curbside_left_, &curbside_right_, [&](double x, int side) {
      const int variant = rng_.integer(0, 2);  // 0 round, 1 square, 2 diamond
      const double plate_z = rng_.uniform(2.1, 2.5);
      const Vector3d base = at(x + 0.15, side, curb_y_ + 0.45, p_.curb_height_m);
      // Plates face oncoming traffic: drivers on the right (y < 0) travel +x, on the left -x.
      const double yaw = side < 0 ? 0.0 : std::numbers::pi;
      addObject("traffic-sign", cls::kTrafficSign, base, yaw, {0.04, 0.64, plate_z + 0.32}, faces[variant], variant,
                Material::kSign);
      builder_.setClass(cls::kPole);
      builder_.setMaterial(Material::kMetal);
      builder_.setMaxEdge(0.5);
      builder_.cylinder(frameAt(base, 0.0), 0.04, 0.0, plate_z + 0.3);
      builder_.setClass(cls::kTrafficSign);
      builder_.setMaterial(Material::kSign);
      builder_.setMaxEdge(0.1);
      const Isometry3d T = frameAt(base, yaw);
      if (variant == 0) {
        Isometry3d disc = T;  // a thin cylinder along -x, in front of the post
        disc.linear() = T.linear() * Eigen::AngleAxisd(-std::numbers::pi / 2, Vector3d::UnitY()).toRotationMatrix();
        disc.translation() = T * Vector3d(-0.05, 0.0, plate_z);
        builder_.cylinder(disc, 0.32, 0.0, 0.02);
      } else {
        Isometry3d plate = T;
        plate.translation() = T * Vector3d(-0.06, 0.0, plate_z);
        if (variant == 2)
          plate.linear() = T.linear() * Eigen::AngleAxisd(std::numbers::pi / 4, Vector3d::UnitX()).toRotationMatrix();
        builder_.box(plate, {-0.01, -0.3, -0.3}, {0.01, 0.3, 0.3}, true);
      }
    });
  }

  void vehicles() {
    const int cars = static_cast<int>(count(p_.cars_per_100m, 10));
    const int trucks = static_cast<int>(count(p_.trucks_per_100m, 1));
    const Vector3f paints[] = {rgb(0.8, 0.8, 0.78),   rgb(0.45, 0.46, 0.48), rgb(0.03, 0.03, 0.035),
                               rgb(0.55, 0.04, 0.03), rgb(0.05, 0.12, 0.45), rgb(0.05, 0.22, 0.1),
                               rgb(0.75, 0.55, 0.05)};
    // Fill both parking lanes front to back with the wanted number of vehicles.
    int cars_left = cars;
    int trucks_left = trucks;
    for (int side : {-1, 1}) {
      const int side_vehicles = side < 0 ? (cars + trucks + 1) / 2 : cars_left + trucks_left;
      const double mean_gap = std::max(0.5, scene_.length_m / std::max(1, side_vehicles) - 5.0);
      double x = rng_.uniform(2.0, 6.0);
      for (int placed = 0; placed < side_vehicles && (cars_left + trucks_left) > 0; ++placed) {
        const bool truck = trucks_left > 0 && (placed == 2 || rng_.uniform() < static_cast<double>(trucks_left) /
                                                                                   (cars_left + trucks_left));
        const int variant = rng_.integer(0, 2);
        const double len = truck ? 7.5 : (variant == 1 ? rng_.uniform(3.9, 4.2) : rng_.uniform(4.5, 4.9));
        const double width = truck ? 2.5 : (variant == 2 ? 1.9 : rng_.uniform(1.72, 1.82));
        if (x + len > scene_.length_m - 2.0) break;
        // Some touch the curb with their tyres; the others stand a little off it. Trucks, wider
        // than the parking lane, always touch it: otherwise the car driving by, which weaves about
        // its lane, would pass through them.
        const bool at_curb = placed == 0 || rng_.chance(0.4);  // at least one a side
        const double drawn = at_curb ? 0.0 : rng_.uniform(0.15, 0.35);  // drawn for trucks too: the same street
        const double off_curb = truck ? 0.0 : drawn;
        const double y_out = curb_y_ - off_curb - width / 2;
        const double yaw = (side < 0 ? 0.0 : std::numbers::pi);
        const Vector3d centre = at(x + len / 2, side, y_out, 0.0);
        if (truck) {
          addObject("truck", cls::kTruck, centre, yaw, {len, width, 3.6}, rgb(0.8, 0.8, 0.8), 0, Material::kCarBody);
          detail::truckShape(builder_, frameAt(centre, yaw), len);
          --trucks_left;
        } else {
          const double height = variant == 2 ? 1.85 : 1.45;
          addObject("car", cls::kCar, centre, yaw, {len, width, height}, paints[rng_.integer(0, 6)], variant,
                    Material::kCarBody);
          detail::carShape(builder_, frameAt(centre, yaw), variant, len, width);
          --cars_left;
        }
        // Bumper to bumper with the next one now and then.
        x += len + ((placed == 0 || rng_.chance(0.25)) ? 0.0 : rng_.uniform(0.5, 2.0 * mean_gap));
      }
    }
  }

  void person(const Vector3d& base, double yaw, const Vector3f& shirt, int variant) {
    const double H = rng_.uniform(1.6, 1.9);
    addObject("person", cls::kPerson, base, yaw, {0.3, 0.5, H}, shirt, variant, Material::kCloth);
    detail::personShape(builder_, base, yaw, H);
  }

  void people() {
    const int n = static_cast<int>(count(p_.people_per_100m, 4));
    const Vector3f shirts[] = {rgb(0.6, 0.1, 0.1),    rgb(0.1, 0.3, 0.6), rgb(0.8, 0.8, 0.75),
                               rgb(0.15, 0.15, 0.15), rgb(0.7, 0.5, 0.1), rgb(0.2, 0.45, 0.2)};
    int placed = 0;
    for (int attempt = 0; attempt < 400 && placed < n; ++attempt) {
      const int side = rng_.chance(0.5) ? 1 : -1;
      const double x = rng_.uniform(5.0, scene_.length_m - 8.0);
      const double r = rng_.uniform();
      // 2: a pair, 1: by a bench, 0: alone; the first two groups are a pair and one by a bench.
      const int group = placed == 0 ? 2 : (placed == 2 ? 1 : (r < 0.35 ? 2 : (r < 0.6 ? 1 : 0)));
      Intervals& walk = side > 0 ? walk_left_ : walk_right_;
      if (!walk.free(x - 1.0, x + 2.5) || !(side > 0 ? curbside_left_ : curbside_right_).free(x - 0.7, x + 2.0))
        continue;
      walk.take(x, x + 1.8);
      const double yaw = (side > 0 ? -1.0 : 1.0) * std::numbers::pi / 2 + rng_.uniform(-0.6, 0.6);
      const double y_out = curb_y_ + rng_.uniform(1.0, p_.sidewalk_width_m - 1.0);
      person(at(x, side, y_out, p_.curb_height_m), yaw, shirts[rng_.integer(0, 5)], 0);
      ++placed;
      if (group == 2) {
        person(at(x + 0.6, side, y_out, p_.curb_height_m), yaw + rng_.uniform(-0.4, 0.4), shirts[rng_.integer(0, 5)],
               0);
        ++placed;
      } else if (group == 1) {
        bench(at(x + 0.3, side, verge_y_ - 0.45, p_.curb_height_m), side);
      }
    }
  }

  void bench(const Vector3d& centre, int side) {
    const double yaw = side > 0 ? 0.0 : std::numbers::pi;
    addObject("bench", cls::kOtherObject, centre, yaw, {1.6, 0.5, 0.85}, rgb(0.35, 0.22, 0.1), 0, Material::kWood);
    const Isometry3d T = frameAt(centre, yaw);
    builder_.setMaxEdge(0.2);
    builder_.box(T, {-0.8, -0.22, 0.42}, {0.8, 0.22, 0.47}, true);  // seat
    builder_.box(T, {-0.8, 0.18, 0.5}, {0.8, 0.23, 0.85}, true);    // back rest
    for (double x : {-0.7, 0.62}) builder_.box(T, {x, -0.2, 0.0}, {x + 0.08, 0.2, 0.42});
  }

  void bicycles() {
    const int n = static_cast<int>(count(p_.bicycles_per_100m, 2));
    const Vector3f frames[] = {rgb(0.1, 0.2, 0.5), rgb(0.5, 0.05, 0.05), rgb(0.1, 0.1, 0.1), rgb(0.6, 0.6, 0.6)};
    scatter(n, 1.8, 1.0, &walk_left_, &walk_right_, [&](double x, int side) {
      const Vector3d base = at(x + 0.9, side, verge_y_ - 0.4, p_.curb_height_m);
      const double yaw = rng_.chance(0.5) ? 0.0 : std::numbers::pi;
      addObject("bicycle", cls::kBicycle, base, yaw, {1.75, 0.5, 1.05}, frames[rng_.integer(0, 3)], 0,
                Material::kMetal);
      detail::bicycleShape(builder_, frameAt(base, yaw));
    });
  }

  SceneParams p_;
  Scene scene_;
  Rng rng_;
  MeshBuilder builder_;
  double road_half_ = 0.0;
  double curb_y_ = 0.0;
  double verge_y_ = 0.0;
  double building_y_ = 0.0;
  Intervals verge_left_, verge_right_, curbside_left_, curbside_right_, walk_left_, walk_right_;
  Intervals fence_left_, fence_right_;
};

}  // namespace

Scene generateScene(const SceneParams& params, double min_length_m) {
  const double length = std::max(params.street_length_m, min_length_m);
  return StreetBuilder(params, length).build();
}

}  // namespace artemis::sim
