// Procedural albedo textures and LiDAR reflectivity. Textures are solid (functions of position in
// the object's frame), deterministic, and carry detail down to a few centimetres so that texture
// accuracy can be measured: asphalt grain and lane paint, paving tiles, bricks and windows, leaves.

#include <algorithm>
#include <cmath>

#include "artemis/sim/scene.hpp"
#include "colour.hpp"
#include "noise.hpp"

namespace artemis::sim {

using Eigen::Vector3d;
using Eigen::Vector3f;

namespace {

using detail::cellOf;
using detail::fbm;
using detail::hash;
using detail::unit;

Vector3f grey(double v) {
  return Vector3f::Constant(static_cast<float>(v));
}
using detail::rgb;

// Fine grain: one random value per `cell` metre cube.
double grain(std::uint64_t seed, const Vector3d& p, double cell) {
  return unit(hash(seed, static_cast<std::uint64_t>(cellOf(p.x(), cell)),
                   static_cast<std::uint64_t>(cellOf(p.y(), cell)), static_cast<std::uint64_t>(cellOf(p.z(), cell))));
}

constexpr std::uint64_t kTextureSeed = 0x7E47u;

Vector3f asphalt(const Vector3d& p, double base) {
  const double patches = fbm(kTextureSeed, p.x(), p.y(), 0.0, 0.15, 3);
  const double g = grain(kTextureSeed + 1, p, 0.02);
  return grey(base * (0.75 + 0.5 * patches) + 0.05 * (g - 0.5));
}

Vector3f paint(const Vector3d& p) {
  const double wear = fbm(kTextureSeed + 2, p.x(), p.y(), 0.0, 2.0, 2);
  return grey(0.55 + 0.3 * wear);
}

Vector3f road(const Vector3d& p, double half_width) {
  const double y = std::abs(p.y());
  const bool centre_dash = std::abs(p.y()) < 0.075 && std::fmod(p.x(), 9.0) < 3.0;
  const bool edge_line = y > half_width - 0.3 && y < half_width - 0.15;
  if (centre_dash || edge_line) return paint(p);
  return asphalt(p, 0.17);
}

Vector3f parking(const Vector3d& p) {
  if (std::fmod(p.x(), 6.0) < 0.12) return paint(p);  // bay lines across the lane
  return asphalt(p, 0.21);
}

Vector3f paving(const Vector3d& p) {
  const double tile = 0.4;
  const double u = p.x() / tile - std::floor(p.x() / tile);
  const double v = p.y() / tile - std::floor(p.y() / tile);
  if (u < 0.03 || v < 0.03) return grey(0.22);  // joints
  const double t = unit(hash(kTextureSeed + 3, static_cast<std::uint64_t>(cellOf(p.x(), tile)),
                             static_cast<std::uint64_t>(cellOf(p.y(), tile))));
  const double g = grain(kTextureSeed + 4, p, 0.015);
  const double v0 = 0.42 * (0.88 + 0.24 * t) + 0.04 * (g - 0.5);
  return rgb(v0 * 1.02, v0, v0 * 0.95);
}

Vector3f grass(const Vector3d& p) {
  const double large = fbm(kTextureSeed + 5, p.x(), p.y(), 0.0, 0.6, 3);
  const double blades = grain(kTextureSeed + 6, p, 0.03);
  const double k = 0.6 + 0.6 * large + 0.3 * (blades - 0.5);
  return rgb(0.10 * k, 0.22 * k, 0.05 * k);
}

// Facade: windows and doors on a grid of floors (3 m) and bays; bricks or plaster in between.
Vector3f facade(const SceneObject& o, const Vector3d& p_O, const Vector3d& n_O, bool brick) {
  const bool front_or_back = std::abs(n_O.y()) >= std::abs(n_O.x());
  const double u = front_or_back ? p_O.x() : std::abs(p_O.y());
  const double wall_length = front_or_back ? o.size_m.x() : o.size_m.y();
  const double v = p_O.z();
  const double bay = 2.5 + 0.35 * o.variant;
  const double floor_h = 3.0;
  const int floor = static_cast<int>(std::floor(v / floor_h));
  const double fv = v - floor * floor_h;
  const auto bay_index = static_cast<std::int64_t>(std::floor(u / bay));
  const double fu = u - static_cast<double>(bay_index) * bay;
  const bool door_bay = floor == 0 && hash(o.instance_id, static_cast<std::uint64_t>(bay_index)) % 4 == 0;
  const bool inner_bay = u > 0.8 && u < wall_length - 0.8 && (u < bay * std::floor(wall_length / bay));
  if (inner_bay && v < o.size_m.z() - 0.8) {
    if (door_bay && std::abs(fu - bay / 2) < 0.55 && fv < 2.2) {
      if (std::abs(fu - bay / 2) > 0.49 || fv > 2.14) return grey(0.75);  // frame
      const double g = grain(kTextureSeed + 7, p_O, 0.05);
      return rgb(0.25 + 0.05 * g, 0.13, 0.06);
    }
    const double w0 = bay / 2 - 0.6;
    const double w1 = bay / 2 + 0.6;
    if (!door_bay && fu > w0 && fu < w1 && fv > 0.9 && fv < 2.4) {
      if (fu < w0 + 0.07 || fu > w1 - 0.07 || fv < 0.97 || fv > 2.33 || std::abs(fu - bay / 2) < 0.03) {
        return grey(0.8);  // frame and mullion
      }
      const double sky = 0.05 + 0.08 * (fv - 0.9) / 1.5;  // reflections brighter towards the top
      return rgb(sky, sky * 1.15, sky * 1.35);
    }
  }
  if (v < 0.5) return o.color * 0.55f;  // plinth
  if (brick) {
    const double course = 0.075;
    const auto row = static_cast<std::int64_t>(std::floor(v / course));
    const double shifted = u + ((row & 1) != 0 ? 0.12 : 0.0);
    const auto col = static_cast<std::int64_t>(std::floor(shifted / 0.24));
    const double bu = shifted - static_cast<double>(col) * 0.24;
    const double bv = v - static_cast<double>(row) * course;
    if (bu < 0.012 || bv < 0.012) return grey(0.5);  // mortar
    const double t = unit(hash(o.instance_id, static_cast<std::uint64_t>(row), static_cast<std::uint64_t>(col)));
    return o.color * static_cast<float>(0.78 + 0.4 * t);
  }
  const double stain = fbm(kTextureSeed + 8, p_O.x(), p_O.y(), p_O.z(), 0.8, 3);
  const double g = grain(kTextureSeed + 9, p_O, 0.02);
  return o.color * static_cast<float>(0.85 + 0.25 * stain + 0.06 * (g - 0.5));
}

Vector3f leaves(const SceneObject& o, const Vector3d& p_S) {
  const double clumps = fbm(kTextureSeed + 10 + o.instance_id, p_S.x(), p_S.y(), p_S.z(), 2.5, 3);
  const double g = grain(kTextureSeed + 11, p_S, 0.04);
  return o.color * static_cast<float>(0.45 + 1.1 * clumps + 0.35 * (g - 0.5));
}

Vector3f bark(const Vector3d& p_S) {
  const double furrows = detail::valueNoise(kTextureSeed + 12, p_S.x() * 25.0, p_S.y() * 25.0, p_S.z() * 2.0);
  return rgb(0.2, 0.13, 0.08) * static_cast<float>(0.6 + 0.6 * furrows);
}

Vector3f sign(const SceneObject& o, const Vector3d& p_O) {
  const double y = p_O.y();
  const double z = p_O.z() - (o.size_m.z() - 0.32);  // from the plate's centre
  const bool border =
      o.variant == 0 ? std::hypot(y, z) > 0.26
                     : (o.variant == 1 ? std::max(std::abs(y), std::abs(z)) > 0.24 : std::abs(y) + std::abs(z) > 0.33);
  if (border) return grey(0.85);
  return o.color;
}

Vector3f carBody(const SceneObject& o, const Vector3d& p_O) {
  const double hl = o.size_m.x() / 2;
  const double hw = o.size_m.y() / 2;
  const bool end = std::abs(p_O.x()) > hl - 0.02;
  const bool lamp_height = p_O.z() > 0.6 && p_O.z() < 0.74;
  const bool lamp_side = std::abs(p_O.y()) > hw - 0.38 && std::abs(p_O.y()) < hw - 0.08;
  if (end && lamp_height && lamp_side) return p_O.x() > 0 ? rgb(0.9, 0.9, 0.8) : rgb(0.7, 0.05, 0.03);
  if (end && p_O.z() < 0.45 && std::abs(p_O.y()) < 0.26 && p_O.z() > 0.33) return grey(0.85);  // number plate
  return o.color;
}

Vector3f carCabin(const SceneObject& o, const Vector3d& p_O, const Vector3d& n_O) {
  // Glass from a little above the body to a little below the roof, pillars at the corners.
  double z0 = 0.0;
  double z1 = 0.0;
  if (o.class_id == cls::kTruck) {
    z0 = 1.6;
    z1 = 2.7;
  } else {
    z0 = (o.variant == 2 ? 1.0 : 0.87) + 0.06;
    z1 = o.size_m.z() - 0.07;
  }
  const bool roof = n_O.z() > 0.9;
  const bool pillar = std::abs(n_O.y()) > 0.5 && std::fmod(std::abs(p_O.x()) + 10.0, 1.1) < 0.08;
  if (!roof && !pillar && p_O.z() > z0 && p_O.z() < z1) {
    const double t = (p_O.z() - z0) / (z1 - z0);
    return rgb(0.04 + 0.06 * t, 0.05 + 0.07 * t, 0.06 + 0.09 * t);
  }
  return o.color;
}

Vector3f cloth(const SceneObject& o, const Vector3d& p_O) {
  const double H = o.size_m.z();
  if (p_O.z() > 0.82 * H + 0.01) {
    if (p_O.z() > 0.95 * H || p_O.x() < -0.02) return rgb(0.12, 0.08, 0.05);  // hair
    return rgb(0.72, 0.52, 0.4);                                              // face
  }
  if (p_O.z() < 0.47 * H) return rgb(0.08, 0.1, 0.2);  // trousers
  return o.color;
}

Vector3f wood(const SceneObject& o, const Vector3d& p_O) {
  const double plank = 0.12;
  const double along = o.kind == "fence" ? p_O.x() : p_O.z();
  const auto k = static_cast<std::int64_t>(std::floor(along / plank));
  if (along - static_cast<double>(k) * plank < 0.012) return o.color * 0.4f;  // gaps
  const double t = unit(hash(o.instance_id, static_cast<std::uint64_t>(k)));
  const double streak = detail::valueNoise(kTextureSeed + 13, p_O.x() * 3.0, p_O.y() * 3.0, p_O.z() * 30.0);
  return o.color * static_cast<float>(0.75 + 0.3 * t + 0.2 * streak);
}

}  // namespace

Vector3f Scene::albedo(std::size_t face, const Vector3d& p_S) const {
  const SceneObject& o = objects[mesh.face_object[face]];
  const Vector3d p_O = o.toObject(p_S);
  Vector3f a = grey(0.5);
  switch (mesh.face_material[face]) {
    case Material::kAsphalt: a = road(p_S, params.lane_width_m); break;
    case Material::kParking: a = parking(p_S); break;
    case Material::kPaving: a = paving(p_S); break;
    case Material::kCurb: a = grey(0.5 + 0.08 * (grain(kTextureSeed + 14, p_S, 0.02) - 0.5)); break;
    case Material::kGrass: a = grass(p_S); break;
    case Material::kBrick:
    case Material::kPlaster: {
      const Vector3d n_S = mesh.faceNormal(face);
      const double c = std::cos(o.yaw_rad);
      const double s = std::sin(o.yaw_rad);
      const Vector3d n_O(c * n_S.x() + s * n_S.y(), -s * n_S.x() + c * n_S.y(), n_S.z());
      a = facade(o, p_O, n_O, mesh.face_material[face] == Material::kBrick);
      break;
    }
    case Material::kRoof:  // weathered roofing: patches and gravel
      a = grey(0.1 + 0.1 * fbm(kTextureSeed + 15, p_S.x(), p_S.y(), 0, 0.8, 3) +
               0.06 * grain(kTextureSeed + 17, p_S, 0.03));
      break;
    case Material::kLeaves: a = leaves(o, p_S); break;
    case Material::kBark: a = bark(p_S); break;
    case Material::kMetal: a = o.color * static_cast<float>(0.9 + 0.2 * grain(kTextureSeed + 16, p_S, 0.05)); break;
    case Material::kSign: a = sign(o, p_O); break;
    case Material::kCarBody: a = carBody(o, p_O); break;
    case Material::kCarCabin: {
      const Vector3d n_S = mesh.faceNormal(face);
      const double c = std::cos(o.yaw_rad);
      const double s = std::sin(o.yaw_rad);
      a = carCabin(o, p_O, {c * n_S.x() + s * n_S.y(), -s * n_S.x() + c * n_S.y(), n_S.z()});
      break;
    }
    case Material::kRubber: a = grey(0.035); break;
    case Material::kCloth: a = cloth(o, p_O); break;
    case Material::kWood: a = wood(o, p_O); break;
    case Material::kCount: a = grey(0.5); break;
  }
  return a.cwiseMax(0.0f).cwiseMin(1.0f);
}

float Scene::reflectivity(std::size_t face, const Vector3d& p_S, double cos_incidence) const {
  const Vector3f a = albedo(face, p_S);
  const double luminance = 0.2126 * a.x() + 0.7152 * a.y() + 0.0722 * a.z();
  double k = 0.25 + 0.75 * luminance;
  if (mesh.face_material[face] == Material::kSign) k = 0.95;  // retro-reflective sheeting
  const double r = k * (0.35 + 0.65 * std::clamp(std::abs(cos_incidence), 0.0, 1.0));
  return static_cast<float>(std::clamp(r, 0.0, 1.0));
}

}  // namespace artemis::sim
