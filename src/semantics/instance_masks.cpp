#include "artemis/semantics/instance_masks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace artemis::semantics {

namespace {

std::string shapesOf(std::span<const onnx::Tensor> outputs) {
  std::string out;
  for (const onnx::Tensor& t : outputs) {
    out += out.empty() ? "[" : ", [";
    for (std::size_t i = 0; i < t.shape.size(); ++i) out += (i > 0 ? ", " : "") + std::to_string(t.shape[i]);
    out += "]";
  }
  return out.empty() ? "nothing" : out;
}

// A detection a model could mean: finite numbers, a box of positive size within a million pixels of
// the input (a model's output is untrusted: NaN or 1e30 would make the mask's pixel arithmetic
// undefined).
bool usable(const Detection& d) {
  constexpr float kFar = 1e6f;
  const auto ok = [](float v) { return std::isfinite(v) && std::abs(v) < kFar; };
  return ok(d.x0) && ok(d.y0) && ok(d.x1) && ok(d.y1) && d.x1 > d.x0 && d.y1 > d.y0 && std::isfinite(d.score) &&
         std::all_of(d.coefficients.begin(), d.coefficients.end(), [](float c) { return std::isfinite(c); });
}

float iouOf(const Detection& a, const Detection& b) {
  const float w = std::max(0.0f, std::min(a.x1, b.x1) - std::max(a.x0, b.x0));
  const float h = std::max(0.0f, std::min(a.y1, b.y1) - std::max(a.y0, b.y0));
  const float inter = w * h;
  const float area = (a.x1 - a.x0) * (a.y1 - a.y0) + (b.x1 - b.x0) * (b.y1 - b.y0) - inter;
  return area > 0.0f ? inter / area : 0.0f;
}

}  // namespace

bool parseLayout(const std::string& name, DetectionLayout& out) {
  for (const auto& [n, l] : {std::pair{"auto", DetectionLayout::kAuto}, std::pair{"dense", DetectionLayout::kDense},
                             std::pair{"dense_transposed", DetectionLayout::kDenseTransposed},
                             std::pair{"end_to_end", DetectionLayout::kEndToEnd}}) {
    if (name == n) {
      out = l;
      return true;
    }
  }
  return false;
}

Result<InstanceOutputs> identifyInstanceOutputs(std::span<const onnx::Tensor> outputs, int labels,
                                                const std::string& model, DetectionLayout layout) {
  InstanceOutputs found;
  found.labels = labels;
  for (const onnx::Tensor& t : outputs) {
    if (t.shape.size() == 4 && t.shape[0] == 1 && t.shape[1] > 0) {
      if (found.prototypes != nullptr) {
        return invalidArgument(
            fmt::format("{}: two 4-D outputs ({}); which are the mask prototypes?", model, shapesOf(outputs)));
      }
      found.prototypes = &t;
    }
  }
  if (found.prototypes == nullptr) {
    return invalidArgument(fmt::format(
        "{}: no mask prototypes (a [1, nm, h, w] output) among its outputs {}: not an instance segmentation model",
        model, shapesOf(outputs)));
  }
  const auto nm = found.prototypes->shape[1];
  found.coefficients = static_cast<int>(nm);
  const std::int64_t dense = 4 + labels + nm;
  const auto fits = [&](const onnx::Tensor& t, DetectionLayout l) {
    switch (l) {
      case DetectionLayout::kDense: return t.shape[1] == dense;
      case DetectionLayout::kEndToEnd: return t.shape[2] == 6 + nm;
      case DetectionLayout::kDenseTransposed: return t.shape[2] == dense;
      case DetectionLayout::kAuto: break;
    }
    return false;
  };
  const std::vector<DetectionLayout> order =
      layout == DetectionLayout::kAuto
          ? std::vector{DetectionLayout::kDense, DetectionLayout::kEndToEnd, DetectionLayout::kDenseTransposed}
          : std::vector{layout};
  for (const DetectionLayout l : order) {
    for (const onnx::Tensor& t : outputs) {
      if (t.shape.size() != 3 || t.shape[0] != 1 || !fits(t, l)) continue;
      found.layout = l;
      found.detections = &t;
      return found;
    }
  }
  return invalidArgument(fmt::format(
      "{}: its outputs {} match no known layout for {} labels and {} prototypes: detections [1, {}, N] "
      "(4 box values, a score per label, a coefficient per prototype), [1, N, {}], or end-to-end [1, K, {}]; "
      "does the config list the model's labels?",
      model, shapesOf(outputs), labels, nm, dense, dense, 6 + nm));
}

std::vector<Detection> readDetections(const InstanceOutputs& outputs, const DetectionParams& params) {
  const onnx::Tensor& t = *outputs.detections;
  const int nc = outputs.labels;
  const int nm = outputs.coefficients;
  std::vector<Detection> out;
  if (outputs.layout == DetectionLayout::kEndToEnd) {
    const auto rows = static_cast<std::size_t>(t.shape[1]);
    const auto stride = static_cast<std::size_t>(t.shape[2]);
    for (std::size_t i = 0; i < rows; ++i) {
      const float* r = &t.values[i * stride];
      // The class column is a float: an index only when it is one of the labels'.
      if (!(r[4] >= params.score_threshold) || !(r[5] > -0.5f && r[5] < static_cast<float>(nc) - 0.5f)) continue;
      Detection d{r[0], r[1], r[2], r[3], r[4], static_cast<int>(std::lround(r[5])), {}};
      d.coefficients.assign(r + 6, r + 6 + nm);
      if (usable(d)) out.push_back(std::move(d));
    }
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.score > b.score; });
    if (out.size() > params.max_detections) out.resize(params.max_detections);
    return out;
  }
  const bool transposed = outputs.layout == DetectionLayout::kDenseTransposed;
  const auto n = static_cast<std::size_t>(transposed ? t.shape[1] : t.shape[2]);
  const auto channels = static_cast<std::size_t>(4 + nc + nm);
  // Value c of candidate i.
  const auto at = [&](std::size_t c, std::size_t i) {
    return transposed ? t.values[i * channels + c] : t.values[c * n + i];
  };
  for (std::size_t i = 0; i < n; ++i) {
    int best = 0;
    float score = -1.0f;
    for (int k = 0; k < nc; ++k) {
      const float s = at(4 + static_cast<std::size_t>(k), i);
      if (s > score) {
        score = s;
        best = k;
      }
    }
    if (!(score >= params.score_threshold)) continue;
    const float cx = at(0, i), cy = at(1, i), w = at(2, i), h = at(3, i);
    Detection d{cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2, score, best, {}};
    d.coefficients.resize(static_cast<std::size_t>(nm));
    for (int k = 0; k < nm; ++k)
      d.coefficients[static_cast<std::size_t>(k)] = at(4 + static_cast<std::size_t>(nc + k), i);
    if (usable(d)) out.push_back(std::move(d));
  }
  return suppress(std::move(out), params.iou_threshold, params.max_detections);
}

std::vector<Detection> suppress(std::vector<Detection> detections, float iou, std::size_t max) {
  std::stable_sort(detections.begin(), detections.end(),
                   [](const auto& a, const auto& b) { return a.score > b.score; });
  std::vector<Detection> kept;
  for (Detection& d : detections) {
    if (kept.size() >= max) break;
    const bool overlapped = std::any_of(kept.begin(), kept.end(),
                                        [&](const Detection& k) { return k.label == d.label && iouOf(k, d) > iou; });
    if (!overlapped) kept.push_back(std::move(d));
  }
  return kept;
}

InstanceMask maskOf(const Detection& detection, const onnx::Tensor& prototypes, const Placement& placement,
                    int input_width, int input_height, float threshold) {
  InstanceMask mask;
  const int nm = static_cast<int>(prototypes.shape[1]);
  const int ph = static_cast<int>(prototypes.shape[2]);
  const int pw = static_cast<int>(prototypes.shape[3]);
  if (nm != static_cast<int>(detection.coefficients.size()) || ph <= 0 || pw <= 0) return mask;
  // The box in image pixels, clipped (in double: boxes are finite and within 1e6 px, usable()).
  const auto clamped = [](double v, int lo, int hi) { return static_cast<int>(std::clamp(v, double(lo), double(hi))); };
  mask.x0 = clamped(std::floor(placement.imageX(detection.x0)), 0, placement.image_width);
  mask.y0 = clamped(std::floor(placement.imageY(detection.y0)), 0, placement.image_height);
  mask.x1 = clamped(std::ceil(placement.imageX(detection.x1)), 0, placement.image_width);
  mask.y1 = clamped(std::ceil(placement.imageY(detection.y1)), 0, placement.image_height);
  if (mask.x1 <= mask.x0 || mask.y1 <= mask.y0) {
    mask.x1 = mask.x0;
    mask.y1 = mask.y0;
    return mask;
  }
  // The mask's logits on the prototype grid, over the box's part of it (one pixel of margin).
  const double gx = static_cast<double>(pw) / input_width;
  const double gy = static_cast<double>(ph) / input_height;
  const int gx0 = clamped(std::floor(detection.x0 * gx) - 1, 0, pw);
  const int gy0 = clamped(std::floor(detection.y0 * gy) - 1, 0, ph);
  const int gx1 = clamped(std::ceil(detection.x1 * gx) + 1, 0, pw);
  const int gy1 = clamped(std::ceil(detection.y1 * gy) + 1, 0, ph);
  const int lw = std::max(0, gx1 - gx0);
  const int lh = std::max(0, gy1 - gy0);
  if (lw == 0 || lh == 0) {  // the box lies off the prototypes
    mask.x1 = mask.x0;
    mask.y1 = mask.y0;
    return mask;
  }
  std::vector<float> logit(static_cast<std::size_t>(lw) * static_cast<std::size_t>(lh), 0.0f);
  const auto plane = static_cast<std::size_t>(ph) * static_cast<std::size_t>(pw);
  for (int k = 0; k < nm; ++k) {
    const float c = detection.coefficients[static_cast<std::size_t>(k)];
    if (c == 0.0f) continue;
    const float* p = prototypes.values.data() + static_cast<std::size_t>(k) * plane;
    for (int y = 0; y < lh; ++y) {
      for (int x = 0; x < lw; ++x) {
        logit[static_cast<std::size_t>(y) * static_cast<std::size_t>(lw) + static_cast<std::size_t>(x)] +=
            c * p[static_cast<std::size_t>(y + gy0) * static_cast<std::size_t>(pw) + static_cast<std::size_t>(x + gx0)];
      }
    }
  }
  const float cut = std::log(threshold / (1.0f - threshold));  // sigmoid(l) > threshold <=> l > cut
  const int bw = mask.x1 - mask.x0;
  mask.inside.assign(static_cast<std::size_t>(bw) * static_cast<std::size_t>(mask.y1 - mask.y0), 0);
  for (int v = mask.y0; v < mask.y1; ++v) {
    const double iy = placement.inputY(v + 0.5);
    if (iy < detection.y0 || iy > detection.y1) continue;
    const double fy = std::clamp(iy * gy - 0.5 - gy0, 0.0, static_cast<double>(lh - 1));
    const int ya = static_cast<int>(fy);
    const int yb = std::min(ya + 1, lh - 1);
    const auto ty = static_cast<float>(fy - ya);
    for (int u = mask.x0; u < mask.x1; ++u) {
      const double ix = placement.inputX(u + 0.5);
      if (ix < detection.x0 || ix > detection.x1) continue;
      const double fx = std::clamp(ix * gx - 0.5 - gx0, 0.0, static_cast<double>(lw - 1));
      const int xa = static_cast<int>(fx);
      const int xb = std::min(xa + 1, lw - 1);
      const auto tx = static_cast<float>(fx - xa);
      const auto l = [&](int x, int y) {
        return logit[static_cast<std::size_t>(y) * static_cast<std::size_t>(lw) + static_cast<std::size_t>(x)];
      };
      const float value =
          (1 - ty) * ((1 - tx) * l(xa, ya) + tx * l(xb, ya)) + ty * ((1 - tx) * l(xa, yb) + tx * l(xb, yb));
      if (value > cut) {
        mask.inside[static_cast<std::size_t>(v - mask.y0) * static_cast<std::size_t>(bw) +
                    static_cast<std::size_t>(u - mask.x0)] = 1;
        ++mask.pixels;
      }
    }
  }
  return mask;
}

}  // namespace artemis::semantics
