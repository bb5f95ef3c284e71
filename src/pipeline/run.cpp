#include "artemis/pipeline/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/pipeline/output_folder.hpp"
#include "artemis/pipeline/segmentation_stage.hpp"
#include "register_step.hpp"
#include "run_outputs.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;

Result<RunReport> runPipeline(datasets::Dataset& dataset, const RunParams& params, const fs::path& out,
                              const std::string& config_json, const ProgressFn& progress) {
  if (params.texture_delay < 0) {
    return invalidArgument(fmt::format("texture_delay must be 0 or more frames, not {}", params.texture_delay));
  }
  if (params.texture_revisit < 0) {
    return invalidArgument(fmt::format("texture_revisit must be 0 or more frames, not {}", params.texture_revisit));
  }
  // Outputs appear together at the end; a failed or killed run leaves `out` as it was.
  auto folder = OutputFolder::open(out, runOutputNames());
  if (!folder) return folder.status();
  if (Status s = writeText(folder->staging() / "config.json", config_json); !s.isOk()) return s;

  RunReport report;
  mapping::Mapper mapper(params.mapper);
  const bool recording_poses = params.use_recording_poses && dataset.hasPoses();
  if (!params.pose_refinement && !recording_poses) {
    return invalidArgument(
        "without the recording's poses, pose refinement must be on (it is the only source of poses)");
  }
  std::unique_ptr<registration::Odometry> odometry;
  if (params.pose_refinement) {
    try {
      odometry = std::make_unique<registration::Odometry>(params.registration);
    } catch (const std::invalid_argument& e) {
      return invalidArgument(e.what());
    }
  }
  RegisterStep register_step(odometry.get(), params.deskew, dataset.root());
  bool warned_vehicle_box = false;
  const SemanticRunParams& sem = params.semantics;
  const bool semantic = sem.segmenter != nullptr;
  if (semantic && (sem.brush == nullptr || sem.vocabulary == nullptr)) {
    return invalidArgument("semantics: a segmenter needs a brush and a vocabulary");
  }
  if (sem.segment_every < 1) return invalidArgument("semantics: segment_every must be >= 1");
  std::size_t unobserved_logged = 0;
  const auto unobserved = [&](std::size_t index, const std::string& why) {
    ++report.frames_unobserved;
    if (++unobserved_logged <= 10) {
      log::warn("frame {}: no semantic observation: {}{}", index, why,
                unobserved_logged == 10 ? " (further frames like this are counted, not logged)" : "");
    }
  };

  // Stage 2's views waiting for later scans (RunParams::texture_delay), oldest first.
  struct DelayedView {
    Frame frame;
    std::size_t camera = 0;  // into frame.cameras
    semantics::SemanticObservation observation;
    bool texture = false;
    bool semantics = false;
    Isometry3d T_W_L = Isometry3d::Identity();
    std::size_t i = 0;  // its place in the range
  };
  std::deque<DelayedView> delayed;
  // Refined textured views kept for their revisit (RunParams::texture_revisit), oldest first.
  struct KeptView {
    CameraView view;
    mapping::ViewMemory memory;
    std::size_t i = 0;
    std::size_t index = 0;  // the frame's
  };
  std::deque<KeptView> kept;
  const bool revisits = params.texture && params.texture_revisit > params.texture_delay;
  // `keep`: the view is kept for a revisit (not after the final meshing: nothing is added since).
  const auto refineView = [&](DelayedView& d, bool keep) {
    Stopwatch refine_clock;
    mapping::ViewMemory memory;
    const mapping::RefinementInput input{&d.frame.cameras[d.camera],
                                         d.texture,
                                         d.semantics ? &d.observation : nullptr,
                                         &d.frame.points_L,
                                         keep && revisits && d.texture ? &memory : nullptr,
                                         sem.vocabulary};
    const mapping::RefinementStats r = mapper.refine(input, d.T_W_L);
    if (!memory.empty()) kept.push_back({std::move(d.frame.cameras[d.camera]), std::move(memory), d.i, d.frame.index});
    report.times.add("refine", refine_clock.elapsedMs());
    report.frames_textured += d.texture ? 1 : 0;
    report.frames_semantic_refined += d.semantics ? 1 : 0;
    log::debug(
        "frame {}: refinement: {} voxels in view, {} faces rendered, {} vertices in view, {} coloured, {} "
        "labelled, gain {:.3f}; cull {:.1f} ms, depth {:.1f} ms, fuse {:.1f} ms",
        d.frame.index, r.voxels_in_view, r.faces_rendered, r.vertices_in_view, r.vertices_updated, r.vertices_labelled,
        r.gain, r.cull_ms, r.depth_ms, r.fuse_ms);
    return r;
  };
  // The voxels of every view refined or revisited in a frame (or at the end), for the observer.
  const auto absorb = [](std::optional<mapping::RefinementStats>& into, mapping::RefinementStats r) {
    if (into) {
      into->voxels.insert(into->voxels.end(), r.voxels.begin(), r.voxels.end());
    } else {
      into = std::move(r);
    }
  };
  const auto revisitView = [&](const KeptView& k) {
    Stopwatch clock;
    const mapping::RefinementStats r = mapper.revisit(k.view, k.memory);
    report.times.add("revisit", clock.elapsedMs());
    log::debug("frame {}: revisit: {} grey vertices added since in view, {} coloured (in {} voxels); {:.1f} ms",
               k.index, r.vertices_in_view, r.vertices_updated, r.voxels_in_view, clock.elapsedMs());
    return r;
  };

  std::string trajectory;
  std::optional<Isometry3d> last_T;  // pose of the last mapped frame
  std::size_t last_i = 0;
  double last_stamp_s = 0.0;
  const std::size_t total = dataset.size();
  // Frame i + 1 is read (scan and image decoded) and segmented while frame i is mapped; "read" is
  // the wait for it.
  // Offline, segmentation rides with the reader; in real time it runs on a worker of its own that
  // takes the newest frame whenever it is free, and its masks are fused when they arrive.
  std::optional<SegmentationStage> segmentation;
  std::unique_ptr<SegmentationWorker> live;
  if (semantic && sem.realtime) {
    live = std::make_unique<SegmentationWorker>(*sem.segmenter);
  } else if (semantic) {
    segmentation.emplace(*sem.segmenter, *sem.brush, sem.camera, sem.segment_every);
  }
  // Masks that arrived from the worker: fused into the cells of their frame's points now, and kept
  // for the frame's stage 2 where its view still waits; after that they come too late.
  const auto acceptLive = [&](std::vector<SegmentationWorker::Done> arrived) {
    for (SegmentationWorker::Done& done : arrived) {
      report.times.add("segment", done.outcome.ms);
      if (!done.outcome.observation.observed) {
        unobserved(done.frame_index, done.outcome.failure);
        continue;
      }
      const auto d = std::find_if(delayed.begin(), delayed.end(), [&](const DelayedView& v) { return v.i == done.i; });
      if (d == delayed.end()) {
        ++report.frames_late;
        continue;
      }
      d->observation = std::move(done.outcome.observation);
      const mapping::SemanticInput input{&d->frame.cameras[d->camera], &d->observation, sem.vocabulary};
      report.times.add("fuse", mapper.fuseLate(d->frame.points_L, d->T_W_L, input).ms);
      d->semantics = params.mapper.refinement.semantic_refinement;
      ++report.frames_observed;
    }
  };
  struct ReadFrame {
    Result<Frame> frame;
    SegmentOutcome segmented;
  };
  const auto read = [&dataset, &segmentation](std::size_t i) {
    ReadFrame r{dataset.frame(i), {}};
    if (r.frame && segmentation) r.segmented = segmentation->segment(i, *r.frame);
    return r;
  };
  std::future<ReadFrame> pending;
  if (total > 0) pending = std::async(std::launch::async, read, std::size_t{0});
  for (std::size_t i = 0; i < total; ++i) {
    // The prior: the recording's motion since the last mapped frame, composed with that frame's
    // (possibly refined) pose; or a constant-velocity guess.
    Isometry3d prior = recording_poses ? dataset.pose(i) : Isometry3d::Identity();
    if (last_T) {
      if (recording_poses) {
        prior = *last_T * dataset.pose(last_i).inverse() * dataset.pose(i);
      } else {
        prior = odometry->predictConstantVelocity(static_cast<int>(i - last_i));
      }
    }
    Stopwatch frame_clock;
    ReadFrame got = pending.get();
    if (i + 1 < total) pending = std::async(std::launch::async, read, i + 1);
    const double read_ms = frame_clock.elapsedMs();
    auto& frame = got.frame;
    if (!frame) {
      log::warn("frame {} skipped: {}", dataset.firstIndex() + i, frame.status().message());
      ++report.frames_failed;
      trajectory += formatRowMajor3x4(prior) + "\n";  // line k stays frame k
      continue;
    }
    const std::size_t frame_index = frame->index;  // the frame may move into the delayed views
    const double frame_stamp_s = frame->stamp_s;
    const Isometry3d T_W_L =
        register_step.run(*frame, prior, last_T, static_cast<int>(i - last_i), last_stamp_s, report);
    // Segmentation ran on the reader's thread; the mapping thread waited for it only where it took
    // longer than mapping the frame before ("segment_wait", left out of "total").
    double segment_wait_ms = 0.0;
    semantics::SemanticObservation observation;
    const CameraView* view = segmentedView(*frame, sem.camera);
    bool offered = false;  // real time: the worker took this frame
    if (live) {
      const std::vector<semantics::ClassId> prompts = sem.brush->beginFrame(i);
      for (const semantics::ClassId c : prompts) mapper.addSemanticClass(c);
      if (i % static_cast<std::size_t>(sem.segment_every) != 0) {
        ++report.frames_not_due;
      } else if (view == nullptr || !view->hasImage()) {
        unobserved(frame->index, view == nullptr ? "the recording has no camera" : "no image " + view->image_path);
      } else {
        if (!view->name.empty()) report.segmented_camera = view->name;
        offered = live->offer({i, frame->index, *view, prompts});
        report.frames_busy += offered ? 0 : 1;
      }
    } else if (semantic) {
      SegmentOutcome& seg = got.segmented;
      for (const semantics::ClassId c : seg.prompts) mapper.addSemanticClass(c);
      if (!seg.due) {
        ++report.frames_not_due;
      } else {
        if (!seg.camera.empty()) report.segmented_camera = seg.camera;
        if (!seg.observation.observed) {
          unobserved(frame->index, seg.failure);
        } else {
          observation = std::move(seg.observation);
          ++report.frames_observed;
        }
        report.times.add("segment", seg.ms);
        segment_wait_ms = std::min(read_ms, seg.ms);
        report.times.add("segment_wait", segment_wait_ms);
      }
    }
    const mapping::SemanticInput semantic_input{view, &observation, sem.vocabulary};
    const mapping::FrameStats stats =
        mapper.integrate(frame->points_L, T_W_L, observation.observed ? &semantic_input : nullptr);
    report.times.add("read", read_ms);
    report.times.add("insert", stats.insert_ms);
    if (params.mapper.free_space.enabled) report.times.add("carve", stats.carve_ms);
    if (semantic && !live) report.times.add("fuse", stats.fuse_ms);
    report.times.add("mesh", stats.mesh_ms);
    if (params.mapper.constraint.enabled) report.times.add("constrain", stats.constrain_ms);
    report.faces_cut += stats.faces_cut;
    report.points_in_vehicle_path += stats.points_in_vehicle_path;
    report.points_carved += stats.points_carved;
    if (stats.points > 0 && stats.points_in_vehicle_path * 20 > stats.points && !warned_vehicle_box) {
      log::warn(
          "frame {}: {} of {} returns lie inside the vehicle's box at this or an earlier pose and were dropped; "
          "if that is more than the vehicle itself and what follows it, the box does not fit this rig "
          "(artemis run --vehicle-box)",
          frame->index, stats.points_in_vehicle_path, stats.points);
      warned_vehicle_box = true;
    }
    // Stage 2: colours (unless the frame is held out of texturing) and classes (when segmented).
    bool texture = false;
    if (params.texture) {
      const bool held_out =
          params.texture_holdout > 0 && (i + 1) % static_cast<std::size_t>(params.texture_holdout) == 0;
      if (held_out) report.held_out_frames.push_back(frame->index);
      texture = !held_out;
    }
    const bool refine_semantics = observation.observed && params.mapper.refinement.semantic_refinement;
    // The view waits texture_delay frames (see RunParams): it is refined once later scans have
    // meshed what it saw.
    std::optional<mapping::RefinementStats> refined;
    if (view != nullptr && view->hasImage() && (texture || refine_semantics || offered)) {
      const auto camera = static_cast<std::size_t>(view - frame->cameras.data());
      delayed.push_back({std::move(*frame), camera, std::move(observation), texture, refine_semantics, T_W_L, i});
    }
    if (live) acceptLive(live->poll());
    // The views now due (one a frame, more after an unreadable frame); the observer hears of all
    // they looked at.
    for (; !delayed.empty() && delayed.front().i + static_cast<std::size_t>(params.texture_delay) <= i;
         delayed.pop_front()) {
      absorb(refined, refineView(delayed.front(), true));
    }
    for (; !kept.empty() && kept.front().i + static_cast<std::size_t>(params.texture_revisit) <= i; kept.pop_front()) {
      absorb(refined, revisitView(kept.front()));
    }
    report.times.add("total", frame_clock.elapsedMs() - segment_wait_ms);
    trajectory += formatRowMajor3x4(T_W_L) + "\n";
    last_T = T_W_L;
    last_i = i;
    last_stamp_s = frame_stamp_s;
    ++report.frames;
    log::debug(
        "frame {}: {} points, {} kept, {} carved of {} tested, {} active voxels, {} meshed, insert {:.1f} ms, carve "
        "{:.1f} ms, mesh "
        "{:.1f} ms, constrain {:.1f} ms ({} of {} patch vertices; patch {:.1f}, build {:.1f}, solve {:.1f} ms; {} "
        "faces cut)",
        frame_index, stats.points, stats.points_kept, stats.points_carved, stats.points_tested_free,
        stats.active_voxels, stats.meshed_voxels, stats.insert_ms, stats.carve_ms, stats.mesh_ms, stats.constrain_ms,
        stats.constraint.active_vertices, stats.constraint.patch_vertices, stats.constraint.patch_ms,
        stats.constraint.build_ms, stats.constraint.solve_ms, stats.faces_cut);
    if (params.observer) {
      params.observer({mapper, i + 1, total, frame_index, T_W_L, refined ? &*refined : nullptr, report.times, false});
    }
    if (progress) progress(i + 1, total);
  }
  if (report.frames == 0) return invalidArgument("no frame could be read; nothing written");
  Stopwatch finish_clock;
  mapper.finish();
  report.finish_ms = finish_clock.elapsedMs();
  report.holes_filled = mapper.holeFilling().filled;
  report.hole_faces = mapper.holeFilling().faces;
  const mapping::HoleFillStats& holes = mapper.holeFilling();
  log::debug(
      "hole filling: {} boundary edges, {} small loops, {} closed with {} faces; left open: {} long edges, {} "
      "islands, {} rough, {} bumpy, {} unclipped; {:.1f} ms",
      holes.boundary_edges, holes.loops, holes.filled, holes.faces, holes.long_edges, holes.islands, holes.rough,
      holes.bumpy, holes.unclipped, holes.ms);
  // The views still waiting, against the final mesh; the observer hears of all they looked at.
  if (live) acceptLive(live->drain());
  std::optional<mapping::RefinementStats> flushed;
  for (; !delayed.empty(); delayed.pop_front()) absorb(flushed, refineView(delayed.front(), false));
  for (; !kept.empty(); kept.pop_front()) absorb(flushed, revisitView(kept.front()));
  if (params.observer) {
    params.observer({mapper, total, total, dataset.firstIndex() + total - 1, last_T.value_or(Isometry3d::Identity()),
                     flushed ? &*flushed : nullptr, report.times, true});
  }
  if (const std::size_t refused = mapper.voxels().rejectedPoints(); refused > 0) {
    log::warn("{} points more than 1000 km from the origin were refused (broken poses?)", refused);
  }
  if (odometry && odometry->map().rejectedPoints() > 0) {
    log::warn("registration: {} points more than 1000 km from the origin were left out of its map (broken poses?)",
              odometry->map().rejectedPoints());
  }
  if (register_step.notDeskewed() > 0) {
    log::warn("{} frames were not deskewed (see above)", register_step.notDeskewed());
  }
  report.vertices = mapper.mesh().vertexCount();
  report.faces = mapper.mesh().faceCount();
  if (Status s = writeRunOutputs(mapper, params, trajectory, odometry != nullptr, folder->staging(), report);
      !s.isOk()) {
    return s;
  }
  if (Status s = folder->commit(); !s.isOk()) return s;
  return report;
}

}  // namespace artemis::pipeline
