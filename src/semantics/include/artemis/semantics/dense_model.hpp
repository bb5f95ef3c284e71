#pragma once
// How to feed and read a dense segmentation network (one score or probability per label and
// pixel), and how its labels become the map's classes. A data file, so that a user brings another
// model by writing another one (README, "Bring your own model"):
//
//   {
//     "name": "enet-cityscapes",
//     "input": {"size_multiple": 8,        pad (zeros, right and bottom) to multiples of this; never stretch
//               "resize_width": 0,         > 0: scale the image to this width first (aspect kept)
//               "scale": 0.0039215686,     value = (pixel - mean) * scale, per channel
//               "mean": [0, 0, 0],
//               "channel_order": "rgb",    or "bgr"
//               "probe_size": [256, 128]}, an input the network accepts: loading runs it once
//     "output": "scores",                  raw scores (a softmax is applied) or "probabilities"
//     "labels": ["Unlabeled", "Road", ...],                 the network's output channels, in order
//     "classes": {"Road": "road", "Sky": null, ...},        label -> vocabulary class; null: none
//     "confusable": [["car", "truck", "other-vehicle", "motorcycle"]]   optional, see below
//   }
//
// Every key of "input" is optional (defaults below). Every label must appear in "classes".
//
// Confusable classes: a network trained on one city's data separates "a vehicle" from "not a
// vehicle" far better than it tells vehicle types apart on another city's images (the shared ENet
// calls many dark KITTI cars Motorcycle). Within a confusable group, the probability of group
// members that were not prompted therefore goes to the prompted members, in proportion to the
// network's own probabilities for them, instead of to "none": asked for cars, a pixel that is 60 %
// Motorcycle and 20 % Car is 80 % car. A group none of whose members was prompted is "none".

#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::semantics {

struct DenseModelInput {
  int size_multiple = 8;
  int resize_width = 0;  // 0: the image's own size
  double scale = 1.0 / 255.0;
  std::array<double, 3> mean{0.0, 0.0, 0.0};
  bool bgr = false;
  std::array<int, 2> probe_size{256, 128};  // width, height
};

struct DenseModelConfig {
  std::string name;
  std::string origin;  // the file it came from (error messages)
  DenseModelInput input;
  bool output_scores = true;           // false: the output is already probabilities
  std::vector<std::string> labels;     // output channel -> the network's label name
  std::vector<ClassId> label_classes;  // output channel -> vocabulary class (kNoClass: none)
  std::vector<std::vector<ClassId>> confusable;

  // Parses the JSON text against `vocabulary`; `origin` names the file in errors.
  static Result<DenseModelConfig> parse(std::string_view json, const std::string& origin, const Vocabulary& vocabulary);
  static Result<DenseModelConfig> load(const std::filesystem::path& path, const Vocabulary& vocabulary);
};

// How the network's label probabilities of a pixel become the observation's channels for a set of
// prompted classes: channel 0 "none", channel k the k-th prompt.
class LabelToPrompts {
 public:
  LabelToPrompts(const DenseModelConfig& config, const std::vector<ClassId>& prompts);
  // `label_p`: the labels' probabilities (config.labels.size() values, summing to 1). Writes
  // prompts.size() + 1 values to `out`, summing to 1.
  void apply(const float* label_p, float* out) const;
  [[nodiscard]] std::size_t channels() const { return channels_; }

 private:
  struct Group {
    std::vector<std::size_t> channels;  // the prompted members' channels
    std::vector<std::size_t> labels;    // labels of its unprompted members: their mass is shared
  };
  std::size_t channels_ = 1;
  std::vector<std::size_t> direct_;  // label -> channel (0: none), for labels not shared by a group
  std::vector<bool> shared_;         // label -> its mass goes to a group's prompted members
  std::vector<Group> groups_;
};

}  // namespace artemis::semantics
