#include "artemis/semantics/simulated_segmenter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "artemis/io/png.hpp"

namespace artemis::semantics {

namespace fs = std::filesystem;

namespace {

// splitmix64: the frame's random numbers come from hashing (seed, frame, stream, index), so every
// draw is reproducible on its own, whatever else was drawn before.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

class Draws {
 public:
  Draws(std::uint64_t seed, std::size_t frame, std::uint64_t stream)
      : base_(
            mix(mix(seed) ^ mix(static_cast<std::uint64_t>(frame) + 0x51ED27ull) ^ (stream * 0xD1B54A32D192ED03ull))) {}
  // Uniform in [0, 1) for item `i`, draw `k`.
  [[nodiscard]] double uniform(std::uint64_t i, std::uint64_t k = 0) const {
    return static_cast<double>(mix(base_ ^ mix(i * 8 + k)) >> 11) * 0x1.0p-53;
  }
  [[nodiscard]] int below(int n, std::uint64_t i, std::uint64_t k) const {
    return std::min(n - 1, static_cast<int>(uniform(i, k) * n));
  }

 private:
  std::uint64_t base_;
};

struct Instance {
  ClassId cls = kNoClass;
  int u0 = 0, v0 = 0, u1 = -1, v1 = -1;  // inclusive pixel bounds
};

// Erodes (radius < 0) or dilates (radius > 0) `m` (w x h, row-major 0/1) with a square of side
// 2|radius|+1, separably via running sums. Windows are clipped at the region's edges.
void morph(std::vector<std::uint8_t>& m, int w, int h, int radius) {
  if (radius == 0) return;
  const int r = std::abs(radius);
  const bool dilate = radius > 0;
  std::vector<std::uint8_t> tmp(m.size());
  std::vector<int> prefix(static_cast<std::size_t>(std::max(w, h)) + 1);
  const auto pass = [&](const std::vector<std::uint8_t>& in, std::vector<std::uint8_t>& out, int n, int lines,
                        auto index) {
    for (int line = 0; line < lines; ++line) {
      prefix[0] = 0;
      for (int x = 0; x < n; ++x)
        prefix[static_cast<std::size_t>(x) + 1] = prefix[static_cast<std::size_t>(x)] + in[index(x, line)];
      for (int x = 0; x < n; ++x) {
        const int a = std::max(0, x - r);
        const int b = std::min(n - 1, x + r);
        const int sum = prefix[static_cast<std::size_t>(b) + 1] - prefix[static_cast<std::size_t>(a)];
        out[index(x, line)] = dilate ? static_cast<std::uint8_t>(sum > 0) : static_cast<std::uint8_t>(sum == b - a + 1);
      }
    }
  };
  pass(m, tmp, w, h, [w](int x, int y) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  });
  pass(tmp, m, h, w, [w](int y, int x) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  });
}

}  // namespace

Result<SegmenterNoise> noiseProfile(const std::string& name) {
  if (name == "none") return SegmenterNoise{};
  SegmenterNoise standard{.miss_rate = 0.10,
                          .max_edge_px = 4,
                          .flip_rate = 0.03,
                          .false_blobs = 1,
                          .blob_area = 0.005,
                          .exact_scores = false};
  if (name == "standard") return standard;
  if (name == "heavy") {
    standard.miss_rate *= 2.0;
    standard.max_edge_px *= 2;
    standard.flip_rate *= 2.0;
    standard.false_blobs *= 2;
    return standard;
  }
  return invalidArgument(fmt::format("unknown segmenter noise '{}' (none, standard or heavy)", name));
}

SimulatedSegmenter::SimulatedSegmenter(fs::path gt_dir, Vocabulary vocabulary, SegmenterNoise noise, std::uint64_t seed)
    : gt_dir_(std::move(gt_dir)), vocabulary_(std::move(vocabulary)), noise_(noise), seed_(seed) {}

Result<std::unique_ptr<SimulatedSegmenter>> SimulatedSegmenter::open(const fs::path& gt_dir,
                                                                     const Vocabulary& vocabulary,
                                                                     const SegmenterNoise& noise, std::uint64_t seed) {
  for (const char* sub : {"semantic_2", "instance_2"}) {
    if (!fs::is_directory(gt_dir / sub)) {
      return notFound(
          fmt::format("{}: no {}/ folder; the simulated segmenter needs the simulator's ground truth "
                      "(the gt/ folder that `artemis sim` writes)",
                      gt_dir.string(), sub));
    }
  }
  return std::unique_ptr<SimulatedSegmenter>(new SimulatedSegmenter(gt_dir, vocabulary, noise, seed));
}

Result<SemanticObservation> SimulatedSegmenter::segment(const SegmentRequest& request,
                                                        std::span<const ClassId> prompts) {
  const std::string file = fmt::format("{:06d}.png", request.frame_index);
  auto classes = io::readPng16(gt_dir_ / "semantic_2" / file);
  if (!classes) return classes.status();
  auto instances = io::readPng16(gt_dir_ / "instance_2" / file);
  if (!instances) return instances.status();
  if (instances->width() != classes->width() || instances->height() != classes->height()) {
    return invalidArgument(fmt::format("{}: {}x{} pixels, but its class image is {}x{}",
                                       (gt_dir_ / "instance_2" / file).string(), instances->width(),
                                       instances->height(), classes->width(), classes->height()));
  }
  if (request.view != nullptr && request.view->hasImage() &&
      (classes->width() != request.view->image.width() || classes->height() != request.view->image.height())) {
    return invalidArgument(fmt::format("{}: {}x{} pixels, but the camera image is {}x{}",
                                       (gt_dir_ / "semantic_2" / file).string(), classes->width(), classes->height(),
                                       request.view->image.width(), request.view->image.height()));
  }
  return corrupt(*classes, *instances, request.frame_index, prompts);
}

SemanticObservation SimulatedSegmenter::corrupt(const ImageU16& classes, const ImageU16& instances,
                                                std::size_t frame_index, std::span<const ClassId> prompts) const {
  const int w = classes.width();
  const int h = classes.height();
  SemanticObservation obs;
  obs.observed = true;
  obs.mask_ids = ImageU16(w, h, 1, 0);
  if (prompts.empty() || w == 0 || h == 0) return obs;
  const auto prompted = [&](ClassId c) { return std::find(prompts.begin(), prompts.end(), c) != prompts.end(); };

  // Instances of prompted classes, keyed by (instance, class): a tree is one instance with a crown
  // (vegetation) and a trunk. std::map: draws follow key order.
  std::map<std::uint32_t, Instance> found;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const ClassId c = vocabulary_.classOfLabel(classes.at(u, v));
      const std::uint16_t inst = instances.at(u, v);
      if (c == kNoClass || inst == 0 || !prompted(c)) continue;
      Instance& in = found[(std::uint32_t{inst} << 8) | c];
      if (in.u1 < 0) {
        in = {c, u, v, u, v};
      } else {
        in.u0 = std::min(in.u0, u);
        in.v0 = std::min(in.v0, v);
        in.u1 = std::max(in.u1, u);
        in.v1 = std::max(in.v1, v);
      }
    }
  }

  const Draws draws(seed_, frame_index, 1);
  const auto paint = [&](std::uint16_t id, int x, int y) {
    std::uint16_t& cur = obs.mask_ids.at(x, y);
    if (cur == 0 || obs.masks[cur - 1].score < obs.masks[id - 1].score) cur = id;
  };
  std::vector<std::uint8_t> region;
  for (const auto& [key, in] : found) {
    const std::uint64_t item = key;
    if (draws.uniform(item, 0) < noise_.miss_rate) continue;
    const int r = noise_.max_edge_px > 0 ? draws.below(noise_.max_edge_px + 1, item, 1) : 0;
    const int radius = draws.uniform(item, 2) < 0.5 ? -r : r;
    const float score = noise_.exact_scores ? 1.0f : static_cast<float>(0.5 + 0.45 * draws.uniform(item, 3));
    // The instance's pixels in its box, padded by the radius: erosion then eats in from the box's
    // sides too, and only the image's border clips it (an object cut by the border stays cut).
    const int pad = r;
    const int u0 = std::max(0, in.u0 - pad);
    const int v0 = std::max(0, in.v0 - pad);
    const int u1 = std::min(w - 1, in.u1 + pad);
    const int v1 = std::min(h - 1, in.v1 + pad);
    const int bw = u1 - u0 + 1;
    const int bh = v1 - v0 + 1;
    region.assign(static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh), 0);
    const std::uint16_t inst = static_cast<std::uint16_t>(key >> 8);
    for (int y = in.v0; y <= in.v1; ++y) {
      for (int x = in.u0; x <= in.u1; ++x) {
        if (instances.at(x, y) == inst && vocabulary_.classOfLabel(classes.at(x, y)) == in.cls) {
          region[static_cast<std::size_t>(y - v0) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(x - u0)] =
              1;
        }
      }
    }
    morph(region, bw, bh, radius);
    obs.masks.push_back({in.cls, score});
    const auto id = static_cast<std::uint16_t>(obs.masks.size());
    for (int y = 0; y < bh; ++y) {
      for (int x = 0; x < bw; ++x) {
        if (region[static_cast<std::size_t>(y) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(x)] != 0) {
          paint(id, u0 + x, v0 + y);
        }
      }
    }
  }

  const std::size_t instance_masks = obs.masks.size();

  // False-positive blobs: discs of a random prompted class with a low score.
  const Draws blob_draws(seed_, frame_index, 2);
  for (int b = 0; b < noise_.false_blobs; ++b) {
    const auto i = static_cast<std::uint64_t>(b);
    const double cu = blob_draws.uniform(i, 0) * w;
    const double cv = blob_draws.uniform(i, 1) * h;
    const ClassId cls = prompts[static_cast<std::size_t>(blob_draws.below(static_cast<int>(prompts.size()), i, 2))];
    const auto score = static_cast<float>(0.3 + 0.4 * blob_draws.uniform(i, 3));
    const double radius = std::sqrt(noise_.blob_area * w * h / std::numbers::pi);
    obs.masks.push_back({cls, score});
    const auto id = static_cast<std::uint16_t>(obs.masks.size());
    for (int y = std::max(0, static_cast<int>(cv - radius)); y <= std::min(h - 1, static_cast<int>(cv + radius)); ++y) {
      for (int x = std::max(0, static_cast<int>(cu - radius)); x <= std::min(w - 1, static_cast<int>(cu + radius));
           ++x) {
        if ((x + 0.5 - cu) * (x + 0.5 - cu) + (y + 0.5 - cv) * (y + 0.5 - cv) <= radius * radius) paint(id, x, y);
      }
    }
  }

  // Flipped pixels: another prompted class, the same score (a pixel-level error inside a mask).
  if (noise_.flip_rate > 0.0 && prompts.size() > 1) {
    const Draws flip_draws(seed_, frame_index, 3);
    std::map<std::pair<std::uint16_t, ClassId>, std::uint16_t> flipped;  // (mask, new class) -> id
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        std::uint16_t& id = obs.mask_ids.at(x, y);
        if (id == 0 || id > instance_masks) continue;
        const auto pixel =
            static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(w) + static_cast<std::uint64_t>(x);
        if (flip_draws.uniform(pixel, 0) >= noise_.flip_rate) continue;
        const Mask from = obs.masks[id - 1];
        // Another class: one of the prompts other than the mask's own.
        int k = flip_draws.below(static_cast<int>(prompts.size()) - 1, pixel, 1);
        ClassId to = kNoClass;
        for (const ClassId c : prompts) {
          if (c == from.class_id) continue;
          if (k-- == 0) {
            to = c;
            break;
          }
        }
        auto [it, added] = flipped.try_emplace({id, to}, std::uint16_t{0});
        if (added) {
          obs.masks.push_back({to, from.score});
          it->second = static_cast<std::uint16_t>(obs.masks.size());
        }
        id = it->second;
      }
    }
  }
  return obs;
}

}  // namespace artemis::semantics
