#include "range_image.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace artemis::mapping::detail {

float fastAtan2(float y, float x) {
  const float ax = std::abs(x);
  const float ay = std::abs(y);
  const float hi = std::max(ax, ay);
  if (hi == 0.0f) return 0.0f;
  const float a = std::min(ax, ay) / hi;  // in [0, 1]
  const float s = a * a;
  // atan on [0, 1], odd polynomial of degree 9 (max error ~1e-5 rad).
  float r = a * (0.9998660f + s * (-0.3302995f + s * (0.1801410f + s * (-0.0851330f + s * 0.0208351f))));
  if (ay > ax) r = std::numbers::pi_v<float> / 2.0f - r;
  if (x < 0.0f) r = std::numbers::pi_v<float> - r;
  return y < 0.0f ? -r : r;
}

RangeImage::RangeImage(float azimuth_step_deg, float elevation_step_deg)
    : azimuth_step_(azimuth_step_deg * std::numbers::pi_v<float> / 180.0f),
      elevation_step_(elevation_step_deg * std::numbers::pi_v<float> / 180.0f) {
  cols_ = std::max(1, static_cast<int>(std::ceil(2.0f * std::numbers::pi_v<float> / azimuth_step_)));
}

int RangeImage::colOf(const Eigen::Vector3f& d) const {
  const float azimuth = fastAtan2(d.y(), d.x()) + std::numbers::pi_v<float>;  // [0, 2 pi]
  const int c = static_cast<int>(azimuth / azimuth_step_);
  return std::clamp(c, 0, cols_ - 1);
}

int RangeImage::rowOf(const Eigen::Vector3f& d) const {
  const float elevation = fastAtan2(d.z(), std::hypot(d.x(), d.y()));
  return static_cast<int>(std::floor((elevation - elevation_min_) / elevation_step_));
}

void RangeImage::build(const std::vector<Eigen::Vector3f>& points_L, float min_range_m, float max_range_m,
                       float grazing_slope) {
  // Directions and angles in parallel (two arctangents a return), then binned in order.
  angles_.resize(points_L.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_L.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      const Eigen::Vector3f& p = points_L[i];
      const float range = p.norm();
      Angles& a = angles_[i];
      a.valid = range >= min_range_m && range <= max_range_m;  // NaN fails both
      if (!a.valid) continue;
      a.ret = {p / range, range, 0};
      a.elevation = fastAtan2(a.ret.direction.z(), std::hypot(a.ret.direction.x(), a.ret.direction.y()));
      a.col = colOf(a.ret.direction);
    }
  });
  float lowest = std::numeric_limits<float>::max();
  float highest = std::numeric_limits<float>::lowest();
  std::size_t valid = 0;
  for (const Angles& a : angles_) {
    if (!a.valid) continue;
    angles_[valid++] = a;
    lowest = std::min(lowest, a.elevation);
    highest = std::max(highest, a.elevation);
  }
  angles_.resize(valid);
  returns_.clear();
  offsets_.clear();
  rows_ = 0;
  if (angles_.empty()) return;
  elevation_min_ = lowest;
  rows_ = static_cast<int>((highest - lowest) / elevation_step_) + 1;
  const std::size_t bins = static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_);
  offsets_.assign(bins + 1, 0);
  bin_of_.resize(angles_.size());
  for (std::size_t i = 0; i < angles_.size(); ++i) {
    const int row = std::clamp(static_cast<int>((angles_[i].elevation - lowest) / elevation_step_), 0, rows_ - 1);
    bin_of_[i] = static_cast<std::uint32_t>(row * cols_ + angles_[i].col);
    angles_[i].ret.bin = bin_of_[i];
    ++offsets_[bin_of_[i] + 1];
  }
  for (std::size_t b = 0; b < bins; ++b) offsets_[b + 1] += offsets_[b];
  returns_.resize(angles_.size());
  fill_.assign(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t i = 0; i < angles_.size(); ++i) returns_[fill_[bin_of_[i]]++] = angles_[i].ret;
  grazing_slope_ = grazing_slope;
  if (grazing_capacity_ < returns_.size()) {
    grazing_capacity_ = returns_.size() + returns_.size() / 4;
    grazing_ = std::make_unique<std::atomic<std::uint8_t>[]>(grazing_capacity_);
    normals_ = std::make_unique<Eigen::Vector3f[]>(grazing_capacity_);
  }
  for (std::size_t k = 0; k < returns_.size(); ++k) grazing_[k].store(0, std::memory_order_relaxed);
  findFarthest();
}

void RangeImage::adoptScratch(RangeImage& other) {
  angles_.swap(other.angles_);
  bin_of_.swap(other.bin_of_);
  fill_.swap(other.fill_);
  scratch_far_.swap(other.scratch_far_);
}

void RangeImage::forgetGrazing() {
  grazing_.reset();
  normals_.reset();
  grazing_capacity_ = 0;
}

void RangeImage::findFarthest() {
  const std::size_t bins = offsets_.size() - 1;
  const auto cols = static_cast<std::size_t>(cols_);
  scratch_far_.assign(bins, 0.0f);  // per bin, then the max over 3 azimuth bins
  farthest_.resize(bins);           // every bin written below
  const auto each_row = [&](const auto& body) {
    tbb::parallel_for(tbb::blocked_range<int>(0, rows_, 8), [&](const auto& r) {
      for (int row = r.begin(); row < r.end(); ++row) body(static_cast<std::size_t>(row));
    });
  };
  each_row([&](std::size_t r) {
    for (std::size_t b = r * cols; b < (r + 1) * cols; ++b) {
      for (std::uint32_t k = offsets_[b]; k < offsets_[b + 1]; ++k) {
        scratch_far_[b] = std::max(scratch_far_[b], returns_[k].range_m);
      }
    }
  });
  // The passes below run along whole rows (no division, and they vectorise): 200,000 bins a frame.
  each_row([&](std::size_t r) {  // the azimuth wraps around at both ends
    const float* row = &scratch_far_[r * cols];
    float* out = &farthest_[r * cols];
    out[0] = std::max({row[cols - 1], row[0], row[1 % cols]});
    for (std::size_t c = 1; c + 1 < cols; ++c) out[c] = std::max(std::max(row[c - 1], row[c]), row[c + 1]);
    if (cols > 1) out[cols - 1] = std::max({row[cols - 2], row[cols - 1], row[0]});
  });
  scratch_far_.swap(farthest_);  // then over 5 elevation bins
  each_row([&](std::size_t r) {
    const std::size_t first = r >= 2 ? r - 2 : 0;
    const std::size_t last = std::min(static_cast<std::size_t>(rows_) - 1, r + 2);
    float* out = &farthest_[r * cols];
    std::copy_n(&scratch_far_[first * cols], cols, out);  // ranges are >= 0: the same as a max with 0
    for (std::size_t dr = first + 1; dr <= last; ++dr) {
      const float* row = &scratch_far_[dr * cols];
      for (std::size_t c = 0; c < cols; ++c) out[c] = std::max(out[c], row[c]);
    }
  });
}

float RangeImage::leastSlope(std::size_t k, int row, int col, int dr, int dc, int reach) const {
  const Return& a = returns_[k];
  float least = std::numeric_limits<float>::infinity();
  for (const int sign : {-1, 1}) {
    for (int step = 1; step <= reach; ++step) {
      const int r = row + sign * step * dr;
      if (r < 0 || r >= rows_) break;
      // Across the beams, the neighbouring beam's return may sit one azimuth bin aside.
      const int spread = dr != 0 ? 1 : 0;
      bool found = false;
      for (int side = -spread; side <= spread; ++side) {
        const int c = wrapped(col + sign * step * dc + side);
        const auto bin = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(c);
        for (std::uint32_t j = offsets_[bin]; j < offsets_[bin + 1]; ++j) {
          const Return& b = returns_[j];
          const float apart = (a.direction - b.direction).norm() * std::min(a.range_m, b.range_m);
          if (!(apart > 0.0f)) continue;
          least = std::min(least, std::abs(a.range_m - b.range_m) / apart);
          found = true;
        }
      }
      if (found) break;  // the nearest occupied bins on this side
    }
  }
  return least;
}

std::int64_t RangeImage::nearestAlong(std::size_t k, int row, int col, int dr, int dc, int sign, int reach) const {
  const Return& a = returns_[k];
  const int spread = dr != 0 ? 1 : 0;  // across the beams, the neighbour may sit one azimuth bin aside
  for (int step = 1; step <= reach; ++step) {
    const int r = row + sign * step * dr;
    if (r < 0 || r >= rows_) return -1;
    std::int64_t best = -1;
    float best_cos = -2.0f;
    for (int side = -spread; side <= spread; ++side) {
      const int c = wrapped(col + sign * step * dc + side);
      const auto bin = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(c);
      for (std::uint32_t j = offsets_[bin]; j < offsets_[bin + 1]; ++j) {
        const float cos = a.direction.dot(returns_[j].direction);
        if (j != k && cos > best_cos) {
          best_cos = cos;
          best = j;
        }
      }
    }
    if (best >= 0) return best;
  }
  return -1;
}

Eigen::Vector3f RangeImage::tangent(std::size_t k, int row, int col, int dr, int dc, int reach) const {
  const std::int64_t before = nearestAlong(k, row, col, dr, dc, -1, reach);
  const std::int64_t after = nearestAlong(k, row, col, dr, dc, 1, reach);
  const auto point = [this](std::size_t j) -> Eigen::Vector3f { return returns_[j].direction * returns_[j].range_m; };
  if (before >= 0 && after >= 0)
    return point(static_cast<std::size_t>(after)) - point(static_cast<std::size_t>(before));
  if (after >= 0) return point(static_cast<std::size_t>(after)) - point(k);
  if (before >= 0) return point(k) - point(static_cast<std::size_t>(before));
  return Eigen::Vector3f::Zero();
}

std::uint8_t RangeImage::classify(std::size_t k) const {
  // Beams lie up to ~0.5 deg apart (two or three elevation bins); a beam's successive returns
  // lie in adjacent azimuth bins.
  const int row = static_cast<int>(returns_[k].bin) / cols_;
  const int col = static_cast<int>(returns_[k].bin) - row * cols_;
  const float along = leastSlope(k, row, col, 0, 1, 2);
  const float across = leastSlope(k, row, col, 1, 0, 3);
  const bool grazing = !(along <= grazing_slope_) || !(across <= grazing_slope_);
  if (grazing) {
    const Eigen::Vector3f n = tangent(k, row, col, 0, 1, 2).cross(tangent(k, row, col, 1, 0, 3));
    const float length = n.norm();
    normals_[k] = length > 1e-6f ? Eigen::Vector3f(n / length) : Eigen::Vector3f::Zero();
  }
  return grazing ? 2 : 1;
}

bool RangeImage::grazing(const Return& q) const {
  const auto k = static_cast<std::size_t>(&q - returns_.data());
  if (!grazing_) throw std::logic_error("RangeImage::grazing: asked after forgetGrazing()");
  std::uint8_t known = grazing_[k].load(std::memory_order_acquire);
  if (known == 0) {
    known = classify(k);
    grazing_[k].store(known, std::memory_order_release);  // any thread works out the same value
  }
  return known == 2;
}

Eigen::Vector3f RangeImage::skimmedNormal(const Return& q) const {
  if (!grazing(q)) return Eigen::Vector3f::Zero();
  return normals_[static_cast<std::size_t>(&q - returns_.data())];
}

}  // namespace artemis::mapping::detail
