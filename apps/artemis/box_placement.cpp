#include "box_placement.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace artemis::cli {

const char* kittiBoxClassName(const std::string& type) {
  if (type == "Car" || type == "Van") return "car";
  if (type == "Pedestrian") return "person";
  if (type == "Cyclist") return "bicyclist";
  return nullptr;
}

namespace {

bool listed(const std::vector<eval::EvaluatedClass>& list, semantics::ClassId id) {
  return std::any_of(list.begin(), list.end(), [&](const eval::EvaluatedClass& c) { return c.id == id; });
}

const semantics::SemanticClass* classOf(const datasets::KittiBox& box, const semantics::Vocabulary& vocabulary) {
  const char* name = kittiBoxClassName(box.type);
  return name != nullptr ? vocabulary.findByName(name) : nullptr;
}

}  // namespace

Result<RunBoxes> placeRunBoxes(const datasets::KittiBoxLabels& labels, const RunClasses& classes,
                               const Isometry3d& T_L_R0, const std::vector<Isometry3d>& T_W_L,
                               const std::function<std::optional<std::size_t>(std::size_t)>& run_frame_of) {
  RunBoxes out;
  for (const auto& box : labels.boxes) {
    const semantics::SemanticClass* cls = classOf(box, classes.vocabulary);
    if (cls == nullptr) continue;
    if (listed(classes.evaluated, cls->id)) {
      if (!listed(out.evaluated, cls->id)) out.evaluated.push_back({cls->id, cls->name});
    } else if (std::find(out.unprompted.begin(), out.unprompted.end(), cls->name) == out.unprompted.end()) {
      out.unprompted.push_back(cls->name);
    }
  }
  if (out.evaluated.empty()) {
    std::string prompted;
    for (const auto& c : classes.evaluated) prompted += (prompted.empty() ? "" : ", ") + c.name;
    return notFound(fmt::format(
        "no box of a class the run prompted ({}); boxed classes: Car/Van -> car, Pedestrian -> person, Cyclist -> "
        "bicyclist",
        prompted));
  }

  // Tracks in the world, from their boxes in the run's frames.
  for (const auto& box : labels.boxes) {
    const auto i = run_frame_of(box.frame);
    if (!i || box.isDontCare() || !labels.has_tracks) continue;
    BoxTrack& track = out.tracks[box.track_id];
    track.type = box.type;
    const Isometry3d T_L_B = datasets::kittiBoxPoseInLidar(box, T_L_R0);
    track.centres_W.push_back(T_W_L.at(*i) * T_L_B * Eigen::Vector3d(0.0, 0.0, 0.5 * box.height_m));
  }
  for (auto& [id, track] : out.tracks) {
    track.travel_m = eval::trackTravelM(track.centres_W);
    track.moving = track.travel_m > kMovingTravelM;
    out.moving_tracks += track.moving ? 1 : 0;
  }

  for (const auto& box : labels.boxes) {
    const auto i = run_frame_of(box.frame);
    if (!i) continue;
    FrameBoxes& frame = out.frames[*i];
    if (box.isDontCare()) {
      frame.dont_care_px.push_back(box.box_2d_px);
      continue;
    }
    eval::TruthBox truth;
    truth.T_F_B = datasets::kittiBoxPoseInLidar(box, T_L_R0);
    truth.size_m = {box.length_m, box.width_m, box.height_m};
    // A box of a class not scored: its points are "not that class", its shell still ignored.
    if (const semantics::SemanticClass* cls = classOf(box, classes.vocabulary)) {
      truth.class_id = listed(out.evaluated, cls->id) ? cls->id : eval::kOutsideBoxes;
    }
    frame.all.push_back(truth);
    const auto track = out.tracks.find(box.track_id);
    if (labels.has_tracks && track != out.tracks.end() && track->second.moving) {
      truth.class_id = eval::kNoSemanticClass;
      truth.size_m.x() += 2.0 * kMovingSlackM;
    }
    frame.static_only.push_back(truth);
  }
  return out;
}

}  // namespace artemis::cli
