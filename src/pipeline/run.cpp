#include "artemis/pipeline/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "artemis/core/archive.hpp"
#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/pipeline/output_folder.hpp"
#include "checkpoint.hpp"
#include "frame_reader.hpp"
#include "pose_track.hpp"
#include "refinement_stage.hpp"
#include "register_step.hpp"
#include "run_outputs.hpp"
#include "semantic_step.hpp"
#include "tile_step.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;

namespace {

Status checkParams(const RunParams& params, bool recording_poses) {
  if (params.texture_delay < 0) {
    return invalidArgument(fmt::format("texture_delay must be 0 or more frames, not {}", params.texture_delay));
  }
  if (params.texture_revisit < 0) {
    return invalidArgument(fmt::format("texture_revisit must be 0 or more frames, not {}", params.texture_revisit));
  }
  if (!params.pose_refinement && !recording_poses) {
    return invalidArgument(
        "without the recording's poses, pose refinement must be on (it is the only source of poses)");
  }
  const SemanticRunParams& sem = params.semantics;
  if (sem.segmenter != nullptr && (sem.brush == nullptr || sem.vocabulary == nullptr)) {
    return invalidArgument("semantics: a segmenter needs a brush and a vocabulary");
  }
  if (sem.segment_every < 1) return invalidArgument("semantics: segment_every must be >= 1");
  return Status::ok();
}

void logFrame(std::size_t frame_index, const mapping::FrameStats& stats) {
  log::debug(
      "frame {}: {} points, {} kept, {} carved of {} tested, {} active voxels, {} meshed, insert {:.1f} ms, carve "
      "{:.1f} ms, stage 2 wait {:.1f} ms, mesh {:.1f} ms, constrain {:.1f} ms (then {:.1f} ms for the looks beside "
      "it; {} of {} patch vertices; patch {:.1f}, build {:.1f}, solve {:.1f} ms; {} faces cut)",
      frame_index, stats.points, stats.points_kept, stats.points_carved, stats.points_tested_free, stats.active_voxels,
      stats.meshed_voxels, stats.insert_ms, stats.carve_ms, stats.stage_two_wait_ms, stats.mesh_ms, stats.constrain_ms,
      stats.beside_constraint_wait_ms,
      stats.constraint.active_vertices, stats.constraint.patch_vertices, stats.constraint.patch_ms,
      stats.constraint.build_ms, stats.constraint.solve_ms, stats.faces_cut);
}

void logHoleFilling(const mapping::HoleFillStats& holes) {
  log::debug(
      "hole filling: {} boundary edges, {} small loops, {} closed with {} faces; left open: {} long edges, {} "
      "islands, {} rough, {} bumpy, {} unclipped; {:.1f} ms",
      holes.boundary_edges, holes.loops, holes.filled, holes.faces, holes.long_edges, holes.islands, holes.rough,
      holes.bumpy, holes.unclipped, holes.ms);
}

// The stages of a run, wired: reading (and offline segmentation) one frame ahead, registration,
// semantics, stage 1 (the mapper), stage 2 (its waiting and kept views). Each stage adds its times
// and counts to the report.
class Run {
 public:
  // `first`: the range frame reading starts at (a resumed run's; load() its state before frame()).
  // `out`: the run's folder (its tiles go there while it runs); `resumed`: it goes on from a checkpoint.
  Run(const datasets::Dataset& dataset, const RunParams& params, bool recording_poses, registration::Odometry* odometry,
      RunReport& report, std::size_t first, const fs::path& out, bool resumed)
      : dataset_(dataset),
        params_(params),
        report_(report),
        mapper_(params.mapper),
        register_(odometry, params.deskew, dataset.root()),
        poses_(dataset, recording_poses, odometry),
        stage2_(mapper_, params, report),
        semantics_(params, mapper_, report),
        tiles_(mapper_, stage2_, report, out, resumed),
        reader_(dataset, semantics_.offline(), first) {}

  // The range's i-th frame through every stage, the tiles it left behind out of memory last; false
  // when it could not be read (logged, counted) or the tiles could not be written (tileError()).
  bool frame(std::size_t i);
  [[nodiscard]] const Status& tileError() const { return tile_error_; }
  // The final meshing, then the views still waiting.
  void finish();
  // After finish(): when tiles left memory, the rest are written and the meshes stitched into
  // `staging` (true), else nothing is done (false).
  Result<bool> finishTiles(const fs::path& staging);
  // Once the outputs are in place.
  void removeRunningTiles() const { tiles_.removeRunningFolder(); }
  // Checkpoints: every stage's state between two frames (in real time, after the segmenter's
  // frame in flight was fused), and back. The odometry is saved by its owner.
  void save(ArchiveWriter& out);
  void load(ArchiveReader& in);
  // After load(): the observer hears of the whole map, as of the frames before `first`.
  void announceResumed(std::size_t first);

  [[nodiscard]] const mapping::Mapper& mapper() const { return mapper_; }
  [[nodiscard]] const std::string& trajectory() const { return poses_.trajectory(); }
  [[nodiscard]] const RunParams& params() const { return params_; }

 private:
  void recordMapping(const mapping::FrameStats& stats, double read_ms, std::size_t frame_index);
  void queueView(std::size_t i, Frame& frame, const CameraView* view, FrameSemantics& semantics,
                 const Isometry3d& T_W_L);
  void warnAboutRefusedPoints() const;

  const datasets::Dataset& dataset_;
  const RunParams& params_;
  RunReport& report_;
  mapping::Mapper mapper_;
  RegisterStep register_;
  PoseTrack poses_;
  RefinementStage stage2_;
  SemanticStep semantics_;
  TileStep tiles_;
  FrameReader reader_;  // last: stopped first, while what it feeds still stands
  bool warned_vehicle_box_ = false;
  Status tile_error_ = Status::ok();
  const bool hand_over_ = !params_.observer && params_.semantics.segmenter == nullptr;
};

bool Run::frame(std::size_t i) {
  const Isometry3d prior = poses_.prior(i);
  Stopwatch frame_clock;
  const double cpu_before = processCpuMs();
  ReadFrame got = reader_.next();
  const double read_ms = frame_clock.elapsedMs();
  if (!got.frame) {
    log::warn("frame {} skipped: {}", dataset_.firstIndex() + i, got.frame.status().message());
    ++report_.frames_failed;
    poses_.skipped(prior);  // line k stays frame k
    return false;
  }
  Frame& frame = *got.frame;
  const std::size_t frame_index = frame.index;  // the frame may move into stage 2
  const double frame_stamp_s = frame.stamp_s;
  const Isometry3d T_W_L =
      register_.run(frame, prior, poses_.lastPose(), poses_.framesSinceLast(i), poses_.lastStamp(), report_);
  if (tile_error_ = tiles_.reloadReturned(T_W_L); !tile_error_.isOk()) return false;
  const CameraView* view = segmentedView(frame, params_.semantics.camera);
  FrameSemantics semantics = semantics_.frame(i, frame, view, got.segmented, read_ms);
  const mapping::SemanticInput semantic_input{view, &semantics.observation, params_.semantics.vocabulary};
  if (hand_over_) stage2_.lookBesideConstraint(i);
  const mapping::FrameStats stats =
      mapper_.integrate(frame.points_L, T_W_L, semantics.observation.observed ? &semantic_input : nullptr);
  recordMapping(stats, read_ms, frame_index);
  queueView(i, frame, view, semantics, T_W_L);
  semantics_.acceptArrived(stage2_);
  // The observer hears of every view stage 2 looked at in this frame. Without one, and without
  // semantics, stage 2 runs beside the next frame's insert (RefinementStage::handOverDue).
  std::optional<mapping::RefinementStats> refined;
  if (hand_over_) {
    stage2_.handOverDue(i);
  } else {
    refined = stage2_.runDue(i);
  }
  const double frame_ms = frame_clock.elapsedMs() - semantics.wait_ms;
  // All threads' work while the frame was mapped (stage 2's and the reader's included): the least a
  // frame can take on N cores is this over N.
  report_.times.add("cpu", processCpuMs() - cpu_before);
  poses_.mapped(i, T_W_L, frame_stamp_s);
  ++report_.frames;
  logFrame(frame_index, stats);
  const std::set<mapping::TileKey>& leaving = tiles_.closeLeftTiles(i, T_W_L);
  if (params_.observer) {
    params_.observer({mapper_, i + 1, dataset_.size(), frame_index, T_W_L, refined ? &*refined : nullptr, report_.times,
                      false, &leaving});
  }
  // After the observer, which was handed this frame's voxel indices: dropping tiles renumbers
  // them. The look's time is the frame's.
  tile_error_ = tiles_.dropClosedTiles();
  report_.times.add("total", frame_ms + tiles_.lookMs());
  return tile_error_.isOk();
}

void Run::recordMapping(const mapping::FrameStats& stats, double read_ms, std::size_t frame_index) {
  report_.times.add("read", read_ms);
  report_.times.add("insert", stats.insert_ms);
  if (params_.mapper.free_space.enabled) report_.times.add("carve", stats.carve_ms);
  if (params_.semantics.segmenter != nullptr && !params_.semantics.realtime) report_.times.add("fuse", stats.fuse_ms);
  report_.times.add("mesh", stats.mesh_ms);
  if (params_.mapper.constraint.enabled) report_.times.add("constrain", stats.constrain_ms);
  report_.faces_cut += stats.faces_cut;
  report_.points_in_vehicle_path += stats.points_in_vehicle_path;
  report_.points_carved += stats.points_carved;
  report_.points_in_finished_tiles += stats.points_in_finished_tiles;
  if (stats.points > 0 && stats.points_in_vehicle_path * 20 > stats.points && !warned_vehicle_box_) {
    log::warn(
        "frame {}: {} of {} returns lie inside the vehicle's box at this or an earlier pose and were dropped; "
        "if that is more than the vehicle itself and what follows it, the box does not fit this rig "
        "(artemis run --vehicle-box)",
        frame_index, stats.points_in_vehicle_path, stats.points);
    warned_vehicle_box_ = true;
  }
}

// Stage 2 of the frame: colours (unless the frame is held out of texturing) and classes (when
// segmented). The view waits texture_delay frames (RunParams) in stage 2.
void Run::queueView(std::size_t i, Frame& frame, const CameraView* view, FrameSemantics& semantics,
                    const Isometry3d& T_W_L) {
  bool texture = false;
  if (params_.texture) {
    const bool held_out =
        params_.texture_holdout > 0 && (i + 1) % static_cast<std::size_t>(params_.texture_holdout) == 0;
    if (held_out) report_.held_out_frames.push_back(frame.index);
    texture = !held_out;
  }
  const bool refine_semantics = semantics.observation.observed && params_.mapper.refinement.semantic_refinement;
  if (view != nullptr && view->hasImage() && (texture || refine_semantics || semantics.offered)) {
    const auto camera = static_cast<std::size_t>(view - frame.cameras.data());
    stage2_.add({std::move(frame), camera, std::move(semantics.observation), texture, refine_semantics, T_W_L, i});
  }
}

void Run::finish() {
  Stopwatch finish_clock;
  mapper_.finish();
  report_.finish_ms = finish_clock.elapsedMs();
  report_.holes_filled = mapper_.holeFilling().filled;
  report_.hole_faces = mapper_.holeFilling().faces;
  logHoleFilling(mapper_.holeFilling());
  // The views still waiting, against the final mesh; the observer hears of all they looked at.
  semantics_.drain(stage2_);
  const std::optional<mapping::RefinementStats> flushed = stage2_.flush();
  if (params_.observer) {
    const std::size_t total = dataset_.size();
    params_.observer({mapper_, total, total, dataset_.firstIndex() + total - 1,
                      poses_.lastPose().value_or(Isometry3d::Identity()), flushed ? &*flushed : nullptr, report_.times,
                      true});
  }
  warnAboutRefusedPoints();
  report_.vertices = mapper_.mesh().vertexCount();
  report_.faces = mapper_.mesh().faceCount();
}

Result<bool> Run::finishTiles(const fs::path& staging) {
  const SemanticRunParams& sem = params_.semantics;
  const bool semantic = sem.segmenter != nullptr;
  const SemanticPlyOptions ply{sem.vocabulary, params_.mapper.semantics.confidence_lambda, sem.write_distribution};
  return tiles_.finish(staging, semantic ? &ply : nullptr, semantic);
}

void Run::save(ArchiveWriter& out) {
  stage2_.complete();
  if (params_.semantics.realtime) semantics_.drain(stage2_);
  out.section("run");
  out.value(static_cast<std::uint8_t>(warned_vehicle_box_));
  poses_.save(out);
  register_.save(out);
  semantics_.save(out);
  mapper_.save(out);
  stage2_.save(out);
  saveReport(out, report_);
}

void Run::load(ArchiveReader& in) {
  in.section("run");
  warned_vehicle_box_ = in.value<std::uint8_t>() != 0;
  poses_.load(in);
  register_.load(in);
  semantics_.load(in);
  mapper_.load(in);
  stage2_.load(in, dataset_);
  loadReport(in, report_);
}

void Run::announceResumed(std::size_t first) {
  if (!params_.observer || first == 0) return;
  params_.observer({mapper_, first, dataset_.size(), dataset_.firstIndex() + first - 1,
                    poses_.lastPose().value_or(Isometry3d::Identity()), nullptr, report_.times, false});
}

void Run::warnAboutRefusedPoints() const {
  if (const std::size_t refused = mapper_.voxels().rejectedPoints(); refused > 0) {
    log::warn("{} points more than 1000 km from the origin were refused (broken poses?)", refused);
  }
  if (register_.odometry() != nullptr && register_.odometry()->map().rejectedPoints() > 0) {
    log::warn("registration: {} points more than 1000 km from the origin were left out of its map (broken poses?)",
              register_.odometry()->map().rejectedPoints());
  }
  if (register_.notDeskewed() > 0) log::warn("{} frames were not deskewed (see above)", register_.notDeskewed());
}

// Where a run stands at a checkpoint: the next range frame, the brush, the odometry, every stage.
Status saveCheckpoint(Run& run, std::size_t next, const registration::Odometry* odometry, const fs::path& out,
                      const std::string& config_json, RunReport& report) {
  Stopwatch clock;
  if (!run.params().resume_record_json.empty()) {
    if (Status s = writeText(out / kResumeRecordFile, run.params().resume_record_json); !s.isOk()) return s;
  }
  ++report.checkpoints;  // counted in the state it writes: a resumed run reports them all
  auto size = writeCheckpoint(out / kCheckpointFile, config_json, [&](ArchiveWriter& state) {
    state.value(static_cast<std::uint64_t>(next));
    saveBrush(state, run.params().semantics.brush);
    state.value(static_cast<std::uint8_t>(odometry != nullptr));
    if (odometry != nullptr) odometry->save(state);
    run.save(state);
  });
  if (!size) return size.status();
  report.checkpoint_mb = static_cast<double>(*size) / (1024.0 * 1024.0);
  report.checkpoint_max_ms = std::max(report.checkpoint_max_ms, clock.elapsedMs());
  log::debug("checkpoint before frame {}: {:.1f} MB in {:.0f} ms", next, report.checkpoint_mb, clock.elapsedMs());
  return Status::ok();
}

// Loads the checkpoint into a run made to start at its frame.
Status loadCheckpoint(const Resumed& resumed, Run& run, registration::Odometry* odometry, const fs::path& out) {
  ArchiveReader in(resumed.state, (out / kCheckpointFile).string());
  try {
    in.value<std::uint64_t>();
    loadBrush(in, nullptr);  // restored before the run was made (restoreBrush)
    const bool has_odometry = in.value<std::uint8_t>() != 0;
    if (has_odometry != (odometry != nullptr)) in.fail("pose refinement was on in one run and off in the other");
    if (odometry != nullptr) odometry->load(in);
    run.load(in);
    if (!in.atEnd()) in.fail("bytes left over after the run's state");
  } catch (const ArchiveError& e) {
    return parseError(e.what());
  }
  return Status::ok();
}

}  // namespace

Result<RunReport> runPipeline(datasets::Dataset& dataset, const RunParams& params, const fs::path& out,
                              const std::string& config_json, const ProgressFn& progress) {
  const bool recording_poses = params.use_recording_poses && dataset.hasPoses();
  if (Status s = checkParams(params, recording_poses); !s.isOk()) return s;
  const std::size_t total = dataset.size();
  std::optional<Resumed> resumed;
  if (params.resume) {
    auto opened = openCheckpoint(out, config_json, total);
    if (!opened) return opened.status();
    resumed = std::move(*opened);
  }
  // Outputs appear together at the end; a failed or killed run leaves `out` as it was.
  auto folder = OutputFolder::open(out, runOutputNames());
  if (!folder) return folder.status();
  if (Status s = writeText(folder->staging() / "config.json", config_json); !s.isOk()) return s;

  std::unique_ptr<registration::Odometry> odometry;
  if (params.pose_refinement) {
    try {
      odometry = std::make_unique<registration::Odometry>(params.registration);
    } catch (const std::invalid_argument& e) {
      return invalidArgument(e.what());
    }
  }
  RunReport report;
  const std::size_t first = resumed ? resumed->next : 0;
  if (resumed) {
    if (Status s = restoreBrush(*resumed, params.semantics.brush, out); !s.isOk()) return s;
  }
  Run run(dataset, params, recording_poses, odometry.get(), report, first, out, resumed.has_value());
  if (resumed) {
    if (Status s = loadCheckpoint(*resumed, run, odometry.get(), out); !s.isOk()) return s;
    resumed.reset();
    report.resumed_at = first;
    run.announceResumed(first);
    log::info("resumed from {} at frame {} of {}", (out / kCheckpointFile).string(), first, total);
  }
  const auto every = static_cast<std::size_t>(std::max(params.checkpoint_every, 0));
  for (std::size_t i = first; i < total; ++i) {
    if (run.frame(i) && progress) progress(i + 1, total, report);
    if (!run.tileError().isOk()) return run.tileError();
    const bool stop = params.stop_requested != nullptr && params.stop_requested->load() && i + 1 < total;
    if ((stop || (every > 0 && (i + 1) % every == 0 && i + 1 < total)) && report.frames > 0) {
      if (Status s = saveCheckpoint(run, i + 1, odometry.get(), out, config_json, report); !s.isOk()) return s;
    }
    if (stop) {
      return Status(
          StatusCode::kInvalidArgument,
          fmt::format("stopped after frame {} of {}: {} holds the run so far; artemis run --resume {} goes on", i + 1,
                      total, (out / kCheckpointFile).string(), out.string()));
    }
  }
  if (report.frames == 0) return invalidArgument("no frame could be read; nothing written");
  run.finish();
  auto tiled = run.finishTiles(folder->staging());
  if (!tiled) return tiled.status();
  if (Status s = writeRunOutputs(run.mapper(), params, run.trajectory(), odometry != nullptr, folder->staging(), report,
                                 *tiled);
      !s.isOk()) {
    return s;
  }
  if (Status s = folder->commit(); !s.isOk()) return s;
  run.removeRunningTiles();
  return report;
}

}  // namespace artemis::pipeline
