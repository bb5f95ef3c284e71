#pragma once
// What the map's geometry says about a class: a likelihood L(geometry | class) that multiplies a
// dense segmenter's per-pixel probabilities before they reach a vertex (fusion, eq. 1, and
// refinement, eq. 13), so that a "car" pixel that bled onto flat road does not make road a car:
//
//   p'(c | pixel, geometry) = p(c | pixel) L(h, n | c) / sum_k p(k | pixel) L(h, n | k)
//
// h is the point's height above the ground nearby (FrameGround), n its surface normal where the
// map has fitted one. The model, per kind of class (the vocabulary's names):
//   - ground (road, parking, sidewalk, other-ground, terrain): 1 up to ground_max_m above the
//     ground, then exp(-(h - ground_max_m) / ground_falloff_m): a kerb is 0.15 m, a car's roof is
//     not road;
//   - objects on the ground (car, truck, other-vehicle, motorcycle, bicycle, person, bicyclist,
//     motorcyclist): object_at_ground below at_ground_m (the road around a tyre; KITTI's boxes
//     ignore their lowest 0.15 m for the same reason), rising linearly to 1 at
//     at_ground_m + ramp_m; also object_at_ground where the surface is flat (|n_z| >=
//     flat_normal_z) and lower than ramp top; above the class's height (vehicle_max_m,
//     large_vehicle_max_m for truck and other-vehicle, person_max_m for people, bicycles and
//     motorcycles) exp(-(h - max) / ground_falloff_m): the tree above a car is not the car;
//   - everything else, and "none": 1.
// Every L is floored at min_likelihood. Where the ground is unknown (h NaN) L = 1: no geometry, no
// opinion.

#include <cstddef>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "artemis/mapping/object_silhouettes.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::mapping {

struct GeometricPriorParams {
  bool enabled = true;
  double ground_max_m = 0.3;
  double ground_falloff_m = 0.3;
  double at_ground_m = 0.12;
  double ramp_m = 0.18;
  double flat_normal_z = 0.9;
  double object_at_ground = 0.05;
  double vehicle_max_m = 2.4;
  double large_vehicle_max_m = 4.5;
  double person_max_m = 2.2;
  double min_likelihood = 0.02;
  // The object-silhouette test of fusion and refinement (object_silhouettes.hpp); apart from
  // `enabled`, which is about the prior above.
  SilhouetteParams silhouettes;
};

class GeometricPrior {
 public:
  enum class Kind { kOther, kGround, kObject };

  // `classes`: the observation's channel classes (kNoClass for "none"), named by `vocabulary`.
  GeometricPrior(const GeometricPriorParams& params, const std::vector<semantics::ClassId>& classes,
                 const semantics::Vocabulary& vocabulary);

  // L for every channel at height `h_m` (NaN: unknown) with unit normal `normal` (nullptr:
  // unknown), into `out` (classes.size() values).
  void likelihoods(float h_m, const Eigen::Vector3f* normal, float* out) const;
  // The kind of a class name (canonical or not).
  static Kind kindOf(std::string_view name, float* max_height_m, const GeometricPriorParams& params);

 private:
  GeometricPriorParams params_;
  std::vector<Kind> kinds_;
  std::vector<float> max_height_m_;
};

}  // namespace artemis::mapping
