#include "artemis/mapping/geometric_prior.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace artemis::mapping {

GeometricPrior::GeometricPrior(const GeometricPriorParams& params, const std::vector<semantics::ClassId>& classes,
                               const semantics::Vocabulary& vocabulary)
    : params_(params) {
  if (!(params.ground_falloff_m > 0.0) || !(params.ramp_m > 0.0) || !(params.min_likelihood > 0.0) ||
      !(params.object_at_ground >= params.min_likelihood && params.object_at_ground <= 1.0)) {
    throw std::invalid_argument(
        "geometric prior: ground_falloff_m and ramp_m must be > 0, min_likelihood > 0 and object_at_ground in "
        "[min_likelihood, 1]");
  }
  for (const semantics::ClassId c : classes) {
    float max_height = 0.0f;
    kinds_.push_back(c == semantics::kNoClass ? Kind::kOther : kindOf(vocabulary.name(c), &max_height, params));
    max_height_m_.push_back(max_height);
  }
}

GeometricPrior::Kind GeometricPrior::kindOf(std::string_view name, float* max_height_m,
                                            const GeometricPriorParams& params) {
  const std::string n = semantics::Vocabulary::canonicalName(name);
  static const std::array<std::string_view, 5> kGround{"road", "parking", "sidewalk", "other-ground", "terrain"};
  if (std::find(kGround.begin(), kGround.end(), n) != kGround.end()) return Kind::kGround;
  double max_height = 0.0;
  if (n == "car") {
    max_height = params.vehicle_max_m;
  } else if (n == "truck" || n == "other-vehicle") {
    max_height = params.large_vehicle_max_m;
  } else if (n == "person" || n == "bicyclist" || n == "motorcyclist" || n == "bicycle" || n == "motorcycle") {
    max_height = params.person_max_m;
  } else {
    return Kind::kOther;
  }
  if (max_height_m != nullptr) *max_height_m = static_cast<float>(max_height);
  return Kind::kObject;
}

void GeometricPrior::likelihoods(float h_m, const Eigen::Vector3f* normal, float* out) const {
  const std::size_t n = kinds_.size();
  if (!params_.enabled || !std::isfinite(h_m)) {
    std::fill(out, out + n, 1.0f);
    return;
  }
  const auto falloff = static_cast<float>(params_.ground_falloff_m);
  const auto floor = static_cast<float>(params_.min_likelihood);
  const auto at_ground = static_cast<float>(params_.at_ground_m);
  const auto ramp = static_cast<float>(params_.ramp_m);
  const auto low = static_cast<float>(params_.object_at_ground);
  const bool flat = normal != nullptr && std::abs(normal->z()) >= static_cast<float>(params_.flat_normal_z);
  for (std::size_t k = 0; k < n; ++k) {
    float l = 1.0f;
    switch (kinds_[k]) {
      case Kind::kGround:
        if (h_m > static_cast<float>(params_.ground_max_m)) {
          l = std::exp(-(h_m - static_cast<float>(params_.ground_max_m)) / falloff);
        }
        break;
      case Kind::kObject:
        if (h_m <= at_ground || (flat && h_m < at_ground + ramp)) {
          l = low;
        } else if (h_m < at_ground + ramp) {
          l = low + (1.0f - low) * (h_m - at_ground) / ramp;
        } else if (h_m > max_height_m_[k]) {
          l = std::exp(-(h_m - max_height_m_[k]) / falloff);
        }
        break;
      case Kind::kOther: break;
    }
    out[k] = std::max(l, floor);
  }
}

}  // namespace artemis::mapping
