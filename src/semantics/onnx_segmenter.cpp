#include "artemis/semantics/onnx_segmenter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace artemis::semantics {

namespace {

// The instance model's image input: the one the config names, or its only one.
Result<onnx::TensorInfo> imageInput(const onnx::Session& s, const NetworkInput& input, const std::string& config) {
  const onnx::TensorInfo* info = nullptr;
  if (!input.name.empty()) {
    info = s.input(input.name);
    if (info == nullptr) {
      std::string names;
      for (const auto& i : s.inputs()) names += (names.empty() ? "" : ", ") + i.name;
      return invalidArgument(fmt::format("{}: instances.input.name is '{}', but {} takes {}", config, input.name,
                                         s.name(), names.empty() ? "no input" : names));
    }
  } else if (s.inputs().size() == 1) {
    info = &s.inputs().front();
  } else {
    return invalidArgument(fmt::format("{}: {} takes {} inputs; name the image in instances.input.name", config,
                                       s.name(), s.inputs().size()));
  }
  if (s.inputs().size() != 1) {
    return invalidArgument(
        fmt::format("{}: {} takes {} inputs; ARTEMIS feeds it one image", config, s.name(), s.inputs().size()));
  }
  const auto& shape = info->shape;
  if (info->type != onnx::ElementType::kFloat || shape.size() != 4 || (shape[1] > 0 && shape[1] != 3)) {
    return invalidArgument(
        fmt::format("{}: {}'s input '{}' is not a float image [1, 3, height, width]", config, s.name(), info->name));
  }
  if ((shape[2] > 0 && shape[2] != input.height) || (shape[3] > 0 && shape[3] != input.width)) {
    return invalidArgument(fmt::format("{}: {} takes {} x {} images but instances.input.size is [{}, {}]", config,
                                       s.name(), shape[3], shape[2], input.width, input.height));
  }
  return *info;
}

}  // namespace

OnnxSegmenter::OnnxSegmenter(OnnxModelConfig config, const Vocabulary& vocabulary)
    : config_(std::move(config)), vocabulary_(vocabulary) {}

Result<std::unique_ptr<OnnxSegmenter>> OnnxSegmenter::open(OnnxModelConfig config, const Vocabulary& vocabulary) {
  std::unique_ptr<OnnxSegmenter> s(new OnnxSegmenter(std::move(config), vocabulary));
  OnnxModelConfig& c = s->config_;
  auto session = onnx::Session::open(c.instances.model, c.runtime);
  if (!session) return session.status();
  s->instances_ = std::move(*session);
  auto input = imageInput(*s->instances_, c.instances.input, c.origin);
  if (!input) return input.status();
  c.instances.input.name = input->name;
  // One run on a blank image: outputs of no known layout are an error now, not at the first frame.
  auto probe = s->instances(ImageU8(c.instances.input.width, c.instances.input.height, 3, 0));
  if (!probe) return probe.status();
  if (c.clip) {
    auto clip = ClipScorer::open(*c.clip, c.runtime);
    if (!clip) return clip.status();
    s->clip_ = std::move(*clip);
  }
  return s;
}

Result<std::vector<OnnxSegmenter::Instance>> OnnxSegmenter::instances(const ImageU8& rgb) {
  const InstanceModelConfig& c = config_.instances;
  if (rgb.channels() != 3 || rgb.empty()) {
    return invalidArgument(
        fmt::format("{}: segments 3-channel colour images, given {} channels", instances_->name(), rgb.channels()));
  }
  const Placement placement = fillInput(rgb, c.input, input_);
  auto outputs = instances_->run(std::span(&input_, 1));
  if (!outputs) return outputs.status();
  auto found = identifyInstanceOutputs(*outputs, static_cast<int>(c.labels.size()), instances_->name(), c.layout);
  if (!found) return found.status();
  std::vector<Instance> out;
  for (Detection& d : readDetections(*found, c.detection)) {
    InstanceMask mask = maskOf(d, *found->prototypes, placement, c.input.width, c.input.height, c.mask_threshold);
    if (mask.pixels == 0) continue;
    out.push_back({std::move(d), std::move(mask)});
  }
  return out;
}

ImageU8 OnnxSegmenter::cropOf(const ImageU8& rgb, const InstanceMask& mask) const {
  // Sampled straight at the CLIP input's size (nearest pixel), so that a frame's crops take the
  // memory of that many small images whatever the masks' sizes.
  const int side = std::max(mask.x1 - mask.x0, mask.y1 - mask.y0);
  const double left = (mask.x0 + mask.x1 - side) / 2.0;
  const double top = (mask.y0 + mask.y1 - side) / 2.0;
  const int cw = clip_->config().image_input.width;
  const int ch = clip_->config().image_input.height;
  const std::array<std::uint8_t, 3> fill = clip_->fillColour();
  ImageU8 crop(cw, ch, 3, 0);
  for (int v = 0; v < ch; ++v) {
    const int y = static_cast<int>(std::floor(top + (v + 0.5) * side / ch));
    for (int u = 0; u < cw; ++u) {
      const int x = static_cast<int>(std::floor(left + (u + 0.5) * side / cw));
      const bool in = mask.contains(x, y);
      for (int k = 0; k < 3; ++k) crop.at(u, v, k) = in ? rgb.at(x, y, k) : fill[static_cast<std::size_t>(k)];
    }
  }
  return crop;
}

Result<SemanticObservation> OnnxSegmenter::segment(const SegmentRequest& request, std::span<const ClassId> prompts) {
  if (request.view == nullptr || !request.view->hasImage() || request.view->image.channels() != 3) {
    return invalidArgument(fmt::format("frame {}: no colour image to segment", request.frame_index));
  }
  const ImageU8& rgb = request.view->image;
  SemanticObservation obs;
  obs.observed = true;
  obs.mask_ids = ImageU16(rgb.width(), rgb.height(), 1, 0);
  if (prompts.empty()) return obs;
  auto found = instances(rgb);
  if (!found) return found.status();
  struct Candidate {
    std::size_t instance;
    ClassId cls;
    float score;
  };
  std::vector<Candidate> candidates;
  if (clip_ == nullptr) {
    for (std::size_t i = 0; i < found->size(); ++i) {
      const ClassId cls = config_.instances.label_classes[static_cast<std::size_t>((*found)[i].detection.label)];
      if (std::find(prompts.begin(), prompts.end(), cls) != prompts.end()) {
        candidates.push_back({i, cls, (*found)[i].detection.score});
      }
    }
  } else if (!found->empty()) {
    std::vector<std::string> names;
    for (const ClassId id : prompts) names.emplace_back(vocabulary_.name(id));
    std::vector<ImageU8> crops;
    for (const Instance& inst : *found) crops.push_back(cropOf(rgb, inst.mask));
    auto probabilities = clip_->classify(crops, names);
    if (!probabilities) return probabilities.status();
    for (std::size_t i = 0; i < found->size(); ++i) {
      const std::vector<double>& p = (*probabilities)[i];
      const auto best = static_cast<std::size_t>(std::max_element(p.begin(), p.end()) - p.begin());
      if (best < prompts.size() && p[best] >= clip_->config().threshold) {
        candidates.push_back({i, prompts[best], static_cast<float>(p[best])});
      }
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& a, const auto& b) { return a.score > b.score; });
  for (const Candidate& c : candidates) {
    const InstanceMask& mask = (*found)[c.instance].mask;
    const auto id = static_cast<std::uint16_t>(obs.masks.size() + 1);
    std::size_t painted = 0;
    for (int v = mask.y0; v < mask.y1; ++v) {
      for (int u = mask.x0; u < mask.x1; ++u) {
        if (!mask.contains(u, v) || obs.mask_ids.at(u, v) != 0) continue;
        obs.mask_ids.at(u, v) = id;
        ++painted;
      }
    }
    if (painted > 0) obs.masks.push_back({c.cls, std::clamp(c.score, 0.0f, 1.0f)});
    if (obs.masks.size() >= 0xFFFF) break;
  }
  return obs;
}

}  // namespace artemis::semantics
