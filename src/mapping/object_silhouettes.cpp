#include "artemis/mapping/object_silhouettes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "artemis/mapping/geometric_prior.hpp"

namespace artemis::mapping {

ObjectSilhouettes::ObjectSilhouettes(const SilhouetteParams& params) : params_(params) {
  if (params.radius_px < 0 || params.radius_px > 256 || !(params.gap_m >= 0.0) || !(params.gap_share >= 0.0) ||
      !std::isfinite(params.min_height_m)) {
    throw std::invalid_argument(
        "object silhouettes: radius_px must be in 0..256, gap_m and gap_share >= 0 and min_height_m finite (got " +
        std::to_string(params.radius_px) + ", " + std::to_string(params.gap_m) + ", " +
        std::to_string(params.gap_share) + ", " + std::to_string(params.min_height_m) + ")");
  }
}

void ObjectSilhouettes::build(const std::vector<DepthProjection::Point>& points, int width, int height,
                              const LabelOf& label_of, const HeightOf& height_of) {
  entries_.clear();
  if (!enabled() || width <= 0 || height <= 0) {
    cols_ = rows_ = 0;
    start_.assign(1, 0);
    return;
  }
  const int r = params_.radius_px;
  cols_ = width / r + 1;
  rows_ = height / r + 1;
  const std::size_t cells = static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_);
  // Counting sort of the labelled returns by cell.
  labelled_.clear();
  start_.assign(cells + 1, 0);
  for (const DepthProjection::Point& p : points) {
    const int u = static_cast<int>(p.pixel % static_cast<std::uint32_t>(width));
    const int v = static_cast<int>(p.pixel / static_cast<std::uint32_t>(width));
    if (v >= height) continue;
    const std::uint32_t label = label_of(u, v);
    if (label == 0 || height_of(p.index) < static_cast<float>(params_.min_height_m)) continue;  // NaN stands
    labelled_.push_back({u, v, p.depth, label});
    ++start_[cellOf(u, v) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  entries_.resize(labelled_.size());
  next_.assign(start_.begin(), start_.end() - 1);
  for (const Entry& e : labelled_) entries_[next_[cellOf(e.u, e.v)]++] = e;
}

std::size_t ObjectSilhouettes::cellOf(int u, int v) const {
  const int r = params_.radius_px;
  return static_cast<std::size_t>(v / r) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(u / r);
}

bool ObjectSilhouettes::behind(int u, int v, float depth_m, std::uint32_t label) const {
  if (label == 0 || cols_ == 0) return false;
  const int r = params_.radius_px;
  const int cu = u / r;
  const int cv = v / r;
  float nearest = depth_m;
  for (int y = std::max(0, cv - 1); y <= std::min(rows_ - 1, cv + 1); ++y) {
    for (int x = std::max(0, cu - 1); x <= std::min(cols_ - 1, cu + 1); ++x) {
      const std::size_t cell =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(x);
      for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
        const Entry& e = entries_[k];
        if (e.label == label && e.depth < nearest && std::abs(e.u - u) <= r && std::abs(e.v - v) <= r) {
          nearest = e.depth;
        }
      }
    }
  }
  return depth_m > nearest + static_cast<float>(params_.gap_m + params_.gap_share * nearest);
}

namespace {

bool isObject(semantics::ClassId c, const semantics::Vocabulary& vocabulary) {
  return c != semantics::kNoClass &&
         GeometricPrior::kindOf(vocabulary.name(c), nullptr, GeometricPriorParams{}) == GeometricPrior::Kind::kObject;
}

}  // namespace

ObjectSilhouettes::LabelOf objectLabels(const semantics::SemanticObservation& observation,
                                        const semantics::Vocabulary& vocabulary) {
  if (observation.isDense()) {
    std::vector<semantics::ClassId> objects;
    for (const semantics::ClassId c : observation.dense.classes) {
      if (isObject(c, vocabulary)) objects.push_back(c);
    }
    const semantics::DenseProbabilities* dense = &observation.dense;
    return [dense, objects = std::move(objects)](int u, int v) -> std::uint32_t {
      const semantics::ClassId c = dense->argmax(u, v);
      return std::find(objects.begin(), objects.end(), c) != objects.end() ? static_cast<std::uint32_t>(c) + 1U : 0U;
    };
  }
  // Masks by class, not by id: one rule whether the segmenter gives a mask per object or per class.
  std::vector<std::uint32_t> label(observation.masks.size() + 1, 0);
  for (std::size_t m = 0; m < observation.masks.size(); ++m) {
    const semantics::ClassId c = observation.masks[m].class_id;
    label[m + 1] = isObject(c, vocabulary) ? static_cast<std::uint32_t>(c) + 1U : 0U;
  }
  const ImageU16* ids = &observation.mask_ids;
  return [ids, label = std::move(label)](int u, int v) -> std::uint32_t {
    if (!ids->contains(u, v)) return 0U;
    const std::uint16_t id = ids->at(u, v);
    return id < label.size() ? label[id] : 0U;
  };
}

}  // namespace artemis::mapping
