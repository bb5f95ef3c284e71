// Movers' shapes: the parked road users' shapes (shapes.cpp), built at the origin of their own
// frame, one small Scene each so that Scene::albedo and Scene::reflectivity texture them.

#include "traffic_shapes.hpp"

#include "colour.hpp"
#include "mesh_builder.hpp"
#include "shapes.hpp"

namespace artemis::sim::detail {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using Eigen::Vector3f;

namespace {

// Starts mover.shape with one object of its own, the next ones added with addPart.
std::uint32_t addPart(Mover& mover, const std::string& kind, std::uint16_t class_id, const Vector3d& size,
                      const Vector3f& color, int variant) {
  SceneObject o;
  o.kind = kind;
  o.class_id = class_id;
  o.instance_id = mover.instance_id;
  o.size_m = size;
  o.color = color;
  o.variant = variant;
  mover.shape.objects.push_back(o);
  return static_cast<std::uint32_t>(mover.shape.objects.size() - 1);
}

void startShape(Mover& mover, const SceneParams& params) {
  mover.shape = Scene{};
  mover.shape.params = params;
  mover.shape.length_m = 0.0;
}

const Vector3f kShirts[] = {rgb(0.6, 0.1, 0.1),    rgb(0.1, 0.3, 0.6), rgb(0.8, 0.8, 0.75),
                            rgb(0.15, 0.15, 0.15), rgb(0.7, 0.5, 0.1), rgb(0.2, 0.45, 0.2)};

}  // namespace

void buildCarShape(Mover& mover, const SceneParams& params, Rng& rng) {
  const Vector3f paints[] = {rgb(0.8, 0.8, 0.78),   rgb(0.45, 0.46, 0.48), rgb(0.03, 0.03, 0.035),
                             rgb(0.55, 0.04, 0.03), rgb(0.05, 0.12, 0.45), rgb(0.05, 0.22, 0.1),
                             rgb(0.75, 0.55, 0.05)};
  const int variant = rng.integer(0, 2);
  const double len = variant == 1 ? rng.uniform(3.9, 4.2) : rng.uniform(4.5, 4.9);
  const double width = variant == 2 ? 1.9 : rng.uniform(1.72, 1.82);
  const double height = variant == 2 ? 1.85 : 1.45;
  startShape(mover, params);
  const std::uint32_t object =
      addPart(mover, "car", cls::kCar, {len, width, height}, paints[rng.integer(0, 6)], variant);
  MeshBuilder builder(mover.shape.mesh, params.max_edge_m);
  builder.setTag(cls::kCar, mover.instance_id, Material::kCarBody, object);
  carShape(builder, Isometry3d::Identity(), variant, len, width);
  mover.half_extent_m = {len / 2, width / 2};
}

void buildCyclistShape(Mover& mover, const SceneParams& params, Rng& rng) {
  const Vector3f frames[] = {rgb(0.1, 0.2, 0.5), rgb(0.5, 0.05, 0.05), rgb(0.1, 0.1, 0.1), rgb(0.6, 0.6, 0.6)};
  const double H = rng.uniform(1.65, 1.9);
  startShape(mover, params);
  // SemanticKITTI labels a bicycle with its rider as the bicyclist, both of them.
  const std::uint32_t bike = addPart(mover, "bicycle", cls::kBicyclist, {1.75, 0.5, 1.05}, frames[rng.integer(0, 3)], 0);
  MeshBuilder builder(mover.shape.mesh, params.max_edge_m);
  builder.setTag(cls::kBicyclist, mover.instance_id, Material::kMetal, bike);
  bicycleShape(builder, Isometry3d::Identity());
  // The rider's clothes follow cloth()'s heights of a person this tall standing.
  const std::uint32_t rider = addPart(mover, "rider", cls::kBicyclist, {0.3, 0.5, H}, kShirts[rng.integer(0, 5)], 0);
  builder.setTag(cls::kBicyclist, mover.instance_id, Material::kCloth, rider);
  riderShape(builder, Isometry3d::Identity(), H);
  mover.half_extent_m = {0.9, 0.3};
}

void buildWalkerShape(Mover& mover, const SceneParams& params, Rng& rng) {
  const double H = rng.uniform(1.6, 1.9);
  startShape(mover, params);
  const std::uint32_t object = addPart(mover, "person", cls::kPerson, {0.3, 0.5, H}, kShirts[rng.integer(0, 5)], 0);
  MeshBuilder builder(mover.shape.mesh, params.max_edge_m);
  builder.setTag(cls::kPerson, mover.instance_id, Material::kCloth, object);
  personShape(builder, Vector3d::Zero(), 0.0, H);
  mover.half_extent_m = {0.2, 0.32};
}

}  // namespace artemis::sim::detail
