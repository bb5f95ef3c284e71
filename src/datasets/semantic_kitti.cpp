#include "artemis/datasets/semantic_kitti.hpp"

#include <algorithm>

namespace artemis::datasets::semantic_kitti {
namespace {

// From semantic-kitti.yaml (labels, color_map given there as BGR and stored here as RGB,
// learning_map). Sorted by id.
constexpr std::array<ClassInfo, 34> kClasses = {{
    {0, "unlabeled", {0, 0, 0}, 0, false},
    {1, "outlier", {255, 0, 0}, 0, false},
    {10, "car", {100, 150, 245}, 1, false},
    {11, "bicycle", {100, 230, 245}, 2, false},
    {13, "bus", {100, 80, 250}, 5, false},
    {15, "motorcycle", {30, 60, 150}, 3, false},
    {16, "on-rails", {0, 0, 255}, 5, false},
    {18, "truck", {80, 30, 180}, 4, false},
    {20, "other-vehicle", {0, 0, 255}, 5, false},
    {30, "person", {255, 30, 30}, 6, false},
    {31, "bicyclist", {255, 40, 200}, 7, false},
    {32, "motorcyclist", {150, 30, 90}, 8, false},
    {40, "road", {255, 0, 255}, 9, false},
    {44, "parking", {255, 150, 255}, 10, false},
    {48, "sidewalk", {75, 0, 75}, 11, false},
    {49, "other-ground", {175, 0, 75}, 12, false},
    {50, "building", {255, 200, 0}, 13, false},
    {51, "fence", {255, 120, 50}, 14, false},
    {52, "other-structure", {255, 150, 0}, 0, false},
    {60, "lane-marking", {150, 255, 170}, 9, false},
    {70, "vegetation", {0, 175, 0}, 15, false},
    {71, "trunk", {135, 60, 0}, 16, false},
    {72, "terrain", {150, 240, 80}, 17, false},
    {80, "pole", {255, 240, 150}, 18, false},
    {81, "traffic-sign", {255, 0, 0}, 19, false},
    {99, "other-object", {50, 255, 255}, 0, false},
    {252, "moving-car", {100, 150, 245}, 1, true},
    {253, "moving-bicyclist", {255, 40, 200}, 7, true},
    {254, "moving-person", {255, 30, 30}, 6, true},
    {255, "moving-motorcyclist", {150, 30, 90}, 8, true},
    {256, "moving-on-rails", {0, 0, 255}, 5, true},
    {257, "moving-bus", {100, 80, 250}, 5, true},
    {258, "moving-truck", {80, 30, 180}, 4, true},
    {259, "moving-other-vehicle", {0, 0, 255}, 5, true},
}};

constexpr std::array<std::string_view, kNumTrainClasses + 1> kTrainNames = {
    "unlabeled", "car",          "bicycle", "motorcycle", "truck",    "other-vehicle", "person",
    "bicyclist", "motorcyclist", "road",    "parking",    "sidewalk", "other-ground",  "building",
    "fence",     "vegetation",   "trunk",   "terrain",    "pole",     "traffic-sign"};

constexpr std::array<std::uint16_t, kNumTrainClasses + 1> kTrainToRaw = {0,  10, 11, 15, 18, 20, 30, 31, 32, 40,
                                                                         44, 48, 49, 50, 51, 70, 71, 72, 80, 81};

}  // namespace

std::span<const ClassInfo> classes() {
  return kClasses;
}

std::optional<ClassInfo> find(std::uint16_t id) {
  const auto it = std::lower_bound(kClasses.begin(), kClasses.end(), id,
                                   [](const ClassInfo& c, std::uint16_t v) { return c.id < v; });
  if (it == kClasses.end() || it->id != id) return std::nullopt;
  return *it;
}

std::uint8_t toTrainId(std::uint16_t id) {
  const auto info = find(id);
  return info ? info->train_id : 0;
}

std::string_view trainName(std::uint8_t train_id) {
  return train_id <= kNumTrainClasses ? kTrainNames[train_id] : std::string_view("unknown");
}

std::uint16_t trainToRawId(std::uint8_t train_id) {
  return train_id <= kNumTrainClasses ? kTrainToRaw[train_id] : 0;
}

}  // namespace artemis::datasets::semantic_kitti
