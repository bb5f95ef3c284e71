#include "box_exclusion.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "artemis/datasets/kitti_raw.hpp"

namespace artemis::cli {

namespace {

// Any class but kNoSemanticClass: boxTruth gives it to the points inside the track's boxes.
constexpr eval::SemanticId kInsideTrack = 1;

std::string trackNames(const std::set<int>& ids) {
  return fmt::format("{}", fmt::join(ids, ","));
}

std::set<int> tracksOf(const datasets::KittiBoxLabels& labels) {
  std::set<int> ids;
  for (const auto& box : labels.boxes) {
    if (!box.isDontCare() && box.track_id >= 0) ids.insert(box.track_id);
  }
  return ids;
}

}  // namespace

Result<std::vector<std::vector<ExclusionBox>>> placeExclusionBoxes(
    const datasets::KittiBoxLabels& labels, const std::set<int>& tracks, const Isometry3d& T_L_R0,
    std::span<const Isometry3d> T_W_L, std::size_t first_index, const BoxExclusionParams& params) {
  if (!(params.length_padding_m >= 0.0) || !(params.side_padding_m >= 0.0)) {
    return invalidArgument(fmt::format("box padding: length {} m, sides {} m: expected values >= 0",
                                       params.length_padding_m, params.side_padding_m));
  }
  if (!tracks.empty() && !labels.has_tracks) {
    return invalidArgument("object labels have no tracks: leaving tracks out needs a tracking label file");
  }
  const std::set<int> known = tracksOf(labels);
  for (int id : tracks) {
    if (known.count(id) == 0) {
      return notFound(fmt::format("track {}: not in the labels (tracks: {})", id, trackNames(known)));
    }
  }
  std::vector<std::vector<ExclusionBox>> out(T_W_L.size());
  const auto n = static_cast<long long>(T_W_L.size());
  const auto reach = static_cast<long long>(params.neighbour_frames);
  for (const auto& box : labels.boxes) {
    if (box.isDontCare() || tracks.count(box.track_id) == 0) continue;
    // Its frame in the range; a box outside the range has no pose to place it with.
    const long long at = static_cast<long long>(box.frame) + params.frame_offset - static_cast<long long>(first_index);
    if (at < 0 || at >= n) continue;
    ExclusionBox grown;
    grown.track_id = box.track_id;
    grown.box_L.size_m = {box.length_m + 2.0 * params.length_padding_m, box.width_m + 2.0 * params.side_padding_m,
                          box.height_m + params.side_padding_m};
    const Isometry3d T_W_B = T_W_L[static_cast<std::size_t>(at)] * datasets::kittiBoxPoseInLidar(box, T_L_R0);
    for (long long i = std::max(0LL, at - reach); i <= std::min(n - 1, at + reach); ++i) {
      grown.box_L.T_F_B = T_W_L[static_cast<std::size_t>(i)].inverse() * T_W_B;
      out[static_cast<std::size_t>(i)].push_back(grown);
    }
  }
  return out;
}

std::map<int, std::size_t> dropPointsInBoxes(PointCloud& points_L, std::span<const ExclusionBox> boxes_L) {
  std::map<int, std::vector<eval::TruthBox>> by_track;
  for (const auto& b : boxes_L) {
    eval::TruthBox box = b.box_L;
    box.class_id = kInsideTrack;
    by_track[b.track_id].push_back(box);
  }
  // The exact box: no shell, no bottom slice (the padding is already in the boxes' sizes).
  const eval::BoxTruthParams exact{.shell_m = 0.0, .bottom_ignore_m = 0.0};
  std::vector<int> owner(points_L.size(), -1);
  std::map<int, std::size_t> dropped;
  for (const auto& [track, boxes] : by_track) {  // ascending ids: the lower id claims a shared point
    const auto truth = eval::boxTruth(points_L.points, boxes, exact);
    for (std::size_t i = 0; i < truth.size(); ++i) {
      if (truth[i] != kInsideTrack || owner[i] >= 0) continue;
      owner[i] = track;
      ++dropped[track];
    }
  }
  points_L.filter([&](std::size_t i) { return owner[i] < 0; });
  return dropped;
}

std::vector<std::uint8_t> pixelsInBoxes(const datasets::KittiBoxLabels& labels, const std::set<int>& tracks,
                                        std::size_t label_frame, int width, int height, int padding_px) {
  std::vector<std::uint8_t> inside(
      static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0)), 0);
  for (const datasets::KittiBox& box : labels.boxes) {
    if (box.frame != label_frame || !tracks.contains(box.track_id)) continue;
    const Eigen::Vector4d& b = box.box_2d_px;
    const auto clampTo = [](double x, int n) {
      return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(n - 1)));
    };
    const int u0 = clampTo(std::floor(b[0]) - padding_px, width);
    const int v0 = clampTo(std::floor(b[1]) - padding_px, height);
    const int u1 = clampTo(std::ceil(b[2]) + padding_px, width);
    const int v1 = clampTo(std::ceil(b[3]) + padding_px, height);
    if (b[2] < 0.0 || b[3] < 0.0 || b[0] > width - 1 || b[1] > height - 1) continue;  // outside the picture
    for (int v = v0; v <= v1; ++v) {
      std::fill_n(inside.begin() + static_cast<std::ptrdiff_t>(v) * width + u0, u1 - u0 + 1, std::uint8_t{1});
    }
  }
  return inside;
}

Result<std::vector<std::vector<ExclusionBox>>> placeTrackBoxes(
    const datasets::Dataset& d, const std::string& labels_path, const std::string& tracks_text,
    std::span<const Isometry3d> T_W_L, const BoxExclusionParams& params, const std::string& boxes_flag,
    const std::string& tracks_flag, std::set<int>* tracks) {
  if (d.format() != "kitti-raw") {
    return invalidArgument(
        fmt::format("{}: a {} recording; {} needs KITTI raw (its calibration R_rect_00 * T_cam0_velo places the boxes)",
                    d.root().string(), d.format(), boxes_flag));
  }
  auto labels = datasets::readKittiBoxes(labels_path);
  if (!labels) return labels.status();
  auto ids = parseTrackList(tracks_text, *labels);
  if (!ids) return Status(ids.status().code(), tracks_flag + ": " + ids.status().message());
  auto T_R0_L = datasets::readKittiRawRectifiedFromLidar(d.root());
  if (!T_R0_L) return T_R0_L.status();
  auto boxes = placeExclusionBoxes(*labels, *ids, T_R0_L->inverse(), T_W_L, d.firstIndex(), params);
  if (!boxes) return Status(boxes.status().code(), labels_path + ": " + boxes.status().message());
  if (tracks != nullptr) *tracks = std::move(*ids);
  return std::move(*boxes);
}

Result<std::set<int>> parseTrackList(const std::string& text, const datasets::KittiBoxLabels& labels) {
  if (text == "all") return tracksOf(labels);
  std::set<int> ids;
  std::stringstream in(text);
  std::string token;
  while (std::getline(in, token, ',')) {
    std::size_t used = 0;
    int id = -1;
    try {
      id = std::stoi(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != token.size() || id < 0) {
      return invalidArgument(fmt::format("track list '{}': '{}' is not a track id (a number >= 0)", text, token));
    }
    ids.insert(id);
  }
  if (ids.empty()) return invalidArgument(fmt::format("track list '{}': no track ids (e.g. 0,1, or all)", text));
  return ids;
}

}  // namespace artemis::cli
