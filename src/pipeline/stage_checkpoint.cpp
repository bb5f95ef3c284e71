// The pipeline stages' state in a checkpoint (see artemis/core/archive.hpp and checkpoint.hpp):
// what each stage carries from one frame to the next, so that a run loaded from it goes on as the
// run that wrote it would have.

#include <string>

#include "artemis/core/archive.hpp"
#include "artemis/pipeline/timing.hpp"
#include "checkpoint.hpp"
#include "pose_track.hpp"
#include "refinement_stage.hpp"
#include "register_step.hpp"
#include "semantic_step.hpp"

namespace artemis::pipeline {

namespace {

void saveView(ArchiveWriter& out, const CameraView& view) {
  out.string(view.name);
  out.value(view.camera);
  out.isometry(view.T_L_C);
  out.image(view.image);
  out.string(view.image_path);
}

CameraView loadView(ArchiveReader& in) {
  CameraView view;
  view.name = in.string(4096);
  in.value(view.camera);
  view.T_L_C = in.isometry();
  view.image = in.image<std::uint8_t>();
  view.image_path = in.string(1 << 16);
  return view;
}

void saveObservation(ArchiveWriter& out, const semantics::SemanticObservation& o) {
  out.value(static_cast<std::uint8_t>(o.observed));
  out.string(o.note);
  out.image(o.mask_ids);
  out.array(o.masks);
  out.value(o.dense.width);
  out.value(o.dense.height);
  out.array(o.dense.classes);
  out.array(o.dense.values);
  out.array(o.dense.top);
}

semantics::SemanticObservation loadObservation(ArchiveReader& in) {
  semantics::SemanticObservation o;
  o.observed = in.value<std::uint8_t>() != 0;
  o.note = in.string(1 << 16);
  o.mask_ids = in.image<std::uint16_t>();
  in.array(o.masks);
  in.value(o.dense.width);
  in.value(o.dense.height);
  in.array(o.dense.classes);
  in.array(o.dense.values);
  in.array(o.dense.top);
  const std::size_t pixels =
      static_cast<std::size_t>(std::max(o.dense.width, 0)) * static_cast<std::size_t>(std::max(o.dense.height, 0));
  if (o.dense.values.size() != pixels * o.dense.classes.size() ||
      (!o.dense.top.empty() && o.dense.top.size() != pixels)) {
    in.fail("a waiting view's class probabilities do not match its size");
  }
  for (const std::uint16_t id : o.mask_ids.data()) {
    if (id > o.masks.size()) in.fail("a waiting view's mask image names a mask it does not have");
  }
  return o;
}

}  // namespace

void saveBrush(ArchiveWriter& out, const semantics::ActiveBrush* brush) {
  out.section("brush");
  out.value(static_cast<std::uint8_t>(brush != nullptr));
  if (brush == nullptr) return;
  const std::vector<semantics::QueryRecord> history = brush->history();
  out.value(static_cast<std::uint64_t>(brush->applied()));
  out.value(static_cast<std::uint64_t>(history.size()));
  for (const semantics::QueryRecord& q : history) {
    out.string(q.text);
    out.array(q.classes);
    out.value(static_cast<std::int64_t>(q.first_frame));
  }
}

void loadBrush(ArchiveReader& in, semantics::ActiveBrush* brush) {
  in.section("brush");
  // Only the first read (restoreBrush) is given the brush; the run's load reads past it.
  const bool had = in.value<std::uint8_t>() != 0;
  if (!had) return;
  const auto applied = in.value<std::uint64_t>();
  std::vector<semantics::QueryRecord> history(static_cast<std::size_t>(in.value<std::uint64_t>()));
  for (semantics::QueryRecord& q : history) {
    q.text = in.string(1 << 16);
    in.array(q.classes);
    q.first_frame = static_cast<std::ptrdiff_t>(in.value<std::int64_t>());
  }
  if (brush != nullptr) brush->restore(std::move(history), static_cast<std::size_t>(applied));
}

void saveReport(ArchiveWriter& out, const RunReport& r) {
  out.section("report");
  for (const std::size_t n :
       {r.frames, r.frames_failed, r.faces_cut, r.points_in_vehicle_path, r.points_carved, r.points_in_finished_tiles,
        r.tiles_finished, r.tiles_reloaded, r.tiles_in_memory, r.registration_fallbacks, r.degenerate_frames,
        r.frames_observed, r.frames_unobserved, r.frames_not_due, r.frames_busy, r.frames_late, r.frames_textured,
        r.frames_semantic_refined}) {
    out.value(static_cast<std::uint64_t>(n));
  }
  r.times.save(out);
  out.value(static_cast<std::uint64_t>(r.registrations.size()));
  for (const registration::FrameRegistration& f : r.registrations) {
    out.isometry(f.T_W_L);
    out.isometry(f.prior_T_W_L);
    out.isometry(f.icp.T_W_L);
    out.value(f.icp.iterations);
    out.value(static_cast<std::uint64_t>(f.icp.correspondences));
    out.value(f.icp.rms_m);
    out.value(static_cast<std::uint8_t>(f.icp.converged));
    out.value(f.icp.degenerate_directions);
    out.value(static_cast<std::uint8_t>(f.icp.used_prior));
    out.value(static_cast<std::uint8_t>(f.fallback));
    out.string(f.reason);
    out.value(f.first_distance_m);
    out.value(static_cast<std::uint64_t>(f.source_points));
    out.value(static_cast<std::uint64_t>(f.map_points));
    for (const double v : {f.correction_m, f.correction_deg, f.ms, f.icp_ms, f.map_ms}) out.value(v);
  }
  out.array(r.registered_frames);
  out.array(r.held_out_frames);
  out.string(r.segmented_camera);
}

void loadReport(ArchiveReader& in, RunReport& r) {
  in.section("report");
  for (std::size_t* n :
       {&r.frames, &r.frames_failed, &r.faces_cut, &r.points_in_vehicle_path, &r.points_carved,
        &r.points_in_finished_tiles, &r.tiles_finished, &r.tiles_reloaded, &r.tiles_in_memory,
        &r.registration_fallbacks, &r.degenerate_frames, &r.frames_observed, &r.frames_unobserved, &r.frames_not_due,
        &r.frames_busy, &r.frames_late, &r.frames_textured, &r.frames_semantic_refined}) {
    *n = static_cast<std::size_t>(in.value<std::uint64_t>());
  }
  r.times.load(in);
  r.registrations.resize(static_cast<std::size_t>(in.value<std::uint64_t>()));
  for (registration::FrameRegistration& f : r.registrations) {
    f.T_W_L = in.isometry();
    f.prior_T_W_L = in.isometry();
    f.icp.T_W_L = in.isometry();
    in.value(f.icp.iterations);
    f.icp.correspondences = static_cast<std::size_t>(in.value<std::uint64_t>());
    in.value(f.icp.rms_m);
    f.icp.converged = in.value<std::uint8_t>() != 0;
    in.value(f.icp.degenerate_directions);
    f.icp.used_prior = in.value<std::uint8_t>() != 0;
    f.fallback = in.value<std::uint8_t>() != 0;
    f.reason = in.string(1 << 16);
    in.value(f.first_distance_m);
    f.source_points = static_cast<std::size_t>(in.value<std::uint64_t>());
    f.map_points = static_cast<std::size_t>(in.value<std::uint64_t>());
    for (double* v : {&f.correction_m, &f.correction_deg, &f.ms, &f.icp_ms, &f.map_ms}) in.value(*v);
  }
  in.array(r.registered_frames);
  in.array(r.held_out_frames);
  r.segmented_camera = in.string(4096);
}

void StageTimes::save(ArchiveWriter& out) const {
  out.value(static_cast<std::uint64_t>(samples_.size()));
  for (const auto& [stage, samples] : samples_) {
    out.string(stage);
    out.array(samples);
  }
}

void StageTimes::load(ArchiveReader& in) {
  samples_.clear();
  const auto stages = in.value<std::uint64_t>();
  for (std::uint64_t s = 0; s < stages; ++s) {
    std::string stage = in.string(256);
    in.array(samples_[stage]);
  }
}

void PoseTrack::save(ArchiveWriter& out) const {
  out.section("pose-track");
  out.value(static_cast<std::uint8_t>(last_T_.has_value()));
  out.isometry(last_T_.value_or(Isometry3d::Identity()));
  out.value(static_cast<std::uint64_t>(last_i_));
  out.value(last_stamp_s_);
  out.string(trajectory_);
}

void PoseTrack::load(ArchiveReader& in) {
  in.section("pose-track");
  const bool has_last = in.value<std::uint8_t>() != 0;
  const Isometry3d last = in.isometry();
  last_T_ = has_last ? std::optional<Isometry3d>(last) : std::nullopt;
  last_i_ = static_cast<std::size_t>(in.value<std::uint64_t>());
  in.value(last_stamp_s_);
  trajectory_ = in.string();
}

void RegisterStep::save(ArchiveWriter& out) const {
  out.section("register");
  out.value(static_cast<std::uint8_t>(warned_no_sweep_));
  out.value(static_cast<std::uint64_t>(not_deskewed_));
}

void RegisterStep::load(ArchiveReader& in) {
  in.section("register");
  warned_no_sweep_ = in.value<std::uint8_t>() != 0;
  not_deskewed_ = static_cast<std::size_t>(in.value<std::uint64_t>());
}

void SemanticStep::save(ArchiveWriter& out) const {
  out.section("semantics");
  out.value(static_cast<std::uint64_t>(unobserved_logged_));
}

void SemanticStep::load(ArchiveReader& in) {
  in.section("semantics");
  unobserved_logged_ = static_cast<std::size_t>(in.value<std::uint64_t>());
}

void RefinementStage::save(ArchiveWriter& out) const {
  out.section("stage-2");
  out.value(static_cast<std::uint64_t>(waiting_.size()));
  for (const WaitingView& w : waiting_) {
    out.value(static_cast<std::uint64_t>(w.frame.index));
    out.value(w.frame.stamp_s);
    out.value(w.frame.scan_start_s);
    out.value(w.frame.scan_end_s);
    out.isometry(w.frame.T_W_L);
    out.cloud(w.frame.points_L);
    out.value(w.frame.stats);
    out.string(w.frame.scan_path);
    saveView(out, w.frame.cameras.at(w.camera));  // the one view stage 2 reads
    saveObservation(out, w.observation);
    out.value(static_cast<std::uint8_t>(w.texture));
    out.value(static_cast<std::uint8_t>(w.semantics));
    out.isometry(w.T_W_L);
    out.value(static_cast<std::uint64_t>(w.i));
  }
  out.value(static_cast<std::uint64_t>(kept_.size()));
  for (const KeptView& k : kept_) {
    out.string(k.view.name);
    out.image(k.memory.depth);
    out.value(k.memory.gain);
    out.isometry(k.memory.T_W_C);
    out.value(k.memory.vertices);
    out.value(static_cast<std::uint64_t>(k.i));
    out.value(static_cast<std::uint64_t>(k.index));
  }
}

void RefinementStage::load(ArchiveReader& in, const datasets::Dataset& dataset) {
  in.section("stage-2");
  waiting_.clear();
  const auto waiting = in.value<std::uint64_t>();
  for (std::uint64_t n = 0; n < waiting; ++n) {
    WaitingView& w = waiting_.emplace_back();
    w.frame.index = static_cast<std::size_t>(in.value<std::uint64_t>());
    in.value(w.frame.stamp_s);
    in.value(w.frame.scan_start_s);
    in.value(w.frame.scan_end_s);
    w.frame.T_W_L = in.isometry();
    w.frame.points_L = in.cloud();
    in.value(w.frame.stats);
    w.frame.scan_path = in.string(1 << 16);
    w.frame.cameras.push_back(loadView(in));
    w.camera = 0;
    w.observation = loadObservation(in);
    w.texture = in.value<std::uint8_t>() != 0;
    w.semantics = in.value<std::uint8_t>() != 0;
    w.T_W_L = in.isometry();
    w.i = static_cast<std::size_t>(in.value<std::uint64_t>());
  }
  kept_.clear();
  const auto kept = in.value<std::uint64_t>();
  for (std::uint64_t n = 0; n < kept; ++n) {
    KeptView k;
    const std::string camera = in.string(4096);
    k.memory.depth = in.image<std::uint16_t>();
    in.value(k.memory.gain);
    k.memory.T_W_C = in.isometry();
    in.value(k.memory.vertices);
    k.i = static_cast<std::size_t>(in.value<std::uint64_t>());
    k.index = static_cast<std::size_t>(in.value<std::uint64_t>());
    if (k.i >= dataset.size()) in.fail("a kept view's frame lies outside the recording's range");
    // The image as the recording holds it: the run read it unchanged.
    auto frame = dataset.frame(k.i);
    if (!frame) in.fail("a kept view's frame cannot be read again: " + frame.status().message());
    for (CameraView& view : frame->cameras) {
      if (view.name == camera) k.view = std::move(view);
    }
    if (!k.view.hasImage() || k.view.image.width() != k.memory.depth.width() ||
        k.view.image.height() != k.memory.depth.height()) {
      in.fail("the image of frame " + std::to_string(k.index) + " (" + camera +
              ") is no longer as the run read it (missing, or of another size)");
    }
    kept_.push_back(std::move(k));
  }
}

}  // namespace artemis::pipeline
