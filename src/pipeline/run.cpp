#include "artemis/pipeline/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "artemis/core/colour.hpp"
#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/pipeline/segmentation_stage.hpp"
#include "artemis/registration/deskew.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;

namespace {

Status writeText(const fs::path& path, const std::string& text) {
  return io::writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

}  // namespace

Status writeMeshPly(const mapping::SemanticMesh& mesh, const fs::path& path, const SemanticPlyOptions* semantics) {
  const auto compact = mesh.compact();
  std::vector<float> xyz(3 * compact.vertex_ids.size());
  std::vector<float> normals(3 * compact.vertex_ids.size());
  for (std::size_t i = 0; i < compact.vertex_ids.size(); ++i) {
    const std::uint32_t v = compact.vertex_ids[i];
    for (int k = 0; k < 3; ++k) {
      xyz[3 * i + static_cast<std::size_t>(k)] = mesh.positions()[v](k);
      normals[3 * i + static_cast<std::size_t>(k)] = mesh.normals()[v](k);
    }
  }
  std::vector<std::uint32_t> triangles;
  triangles.reserve(3 * compact.faces.size());
  for (const auto& f : compact.faces) triangles.insert(triangles.end(), f.begin(), f.end());
  // Texture: the colour means, linear RGB encoded as 8-bit sRGB; grey where no view coloured a vertex.
  std::vector<std::uint8_t> rgb;
  bool textured = false;
  for (const std::uint32_t v : compact.vertex_ids) textured = textured || mesh.hasColour(v);
  if (textured) {
    rgb.resize(3 * compact.vertex_ids.size(), 128);
    for (std::size_t i = 0; i < compact.vertex_ids.size(); ++i) {
      if (!mesh.hasColour(compact.vertex_ids[i])) continue;
      const Eigen::Vector3f c = mesh.colourMean(compact.vertex_ids[i]);
      for (int k = 0; k < 3; ++k) {
        rgb[3 * i + static_cast<std::size_t>(k)] =
            static_cast<std::uint8_t>(std::lround(255.0 * srgbEncode(static_cast<double>(c(k)))));
      }
    }
  }
  io::PlyData ply =
      io::makePlyMesh({.xyz = &xyz, .normals = &normals, .rgb = textured ? &rgb : nullptr, .triangles = &triangles});
  ply.comments.push_back("ARTEMIS Living Map: world frame, normals towards the sensor");
  if (semantics != nullptr && semantics->vocabulary != nullptr) {
    const std::size_t n = compact.vertex_ids.size();
    std::vector<std::uint8_t> class_id(n);
    std::vector<float> confidence(n);
    for (std::size_t i = 0; i < n; ++i) {
      class_id[i] = mesh.vertexClass(compact.vertex_ids[i]);
      confidence[i] = mesh.confidence(compact.vertex_ids[i], semantics->confidence_lambda);
    }
    ply.comments.push_back("class_id: vocabulary id (see semantics.json; 0: none), confidence: 1 - exp(-lambda W_sem)");
    if (Status s = ply.setScalar("vertex", "class_id", std::move(class_id)); !s.isOk()) return s;
    if (Status s = ply.setScalar("vertex", "confidence", std::move(confidence)); !s.isOk()) return s;
    if (semantics->distribution) {
      const auto& slots = mesh.semanticSlots();
      std::vector<std::vector<float>> p(slots.size(), std::vector<float>(n, 0.0f));
      std::vector<float> d(slots.size());
      for (std::size_t i = 0; i < n; ++i) {
        if (!mesh.distribution(compact.vertex_ids[i], d.data())) continue;
        for (std::size_t slot = 0; slot < slots.size(); ++slot) p[slot][i] = d[slot];
      }
      for (std::size_t slot = 0; slot < slots.size(); ++slot) {
        std::string name(semantics->vocabulary->name(slots[slot]));
        std::replace(name.begin(), name.end(), '-', '_');
        if (Status s = ply.setScalar("vertex", "prob_" + name, std::move(p[slot])); !s.isOk()) return s;
      }
    }
  }
  return io::writePly(path, ply);
}

Status writeClassColouredPly(const mapping::SemanticMesh& mesh, const semantics::Vocabulary& vocabulary,
                             const fs::path& path) {
  const auto compact = mesh.compact();
  std::vector<float> xyz(3 * compact.vertex_ids.size());
  std::vector<std::uint8_t> rgb(3 * compact.vertex_ids.size());
  for (std::size_t i = 0; i < compact.vertex_ids.size(); ++i) {
    const std::uint32_t v = compact.vertex_ids[i];
    const auto colour = vocabulary.colour(mesh.vertexClass(v));
    for (std::size_t k = 0; k < 3; ++k) {
      xyz[3 * i + k] = mesh.positions()[v](static_cast<Eigen::Index>(k));
      rgb[3 * i + k] = colour[k];
    }
  }
  std::vector<std::uint32_t> triangles;
  triangles.reserve(3 * compact.faces.size());
  for (const auto& f : compact.faces) triangles.insert(triangles.end(), f.begin(), f.end());
  io::PlyData ply = io::makePlyMesh({.xyz = &xyz, .normals = nullptr, .rgb = &rgb, .triangles = &triangles});
  ply.comments.push_back("ARTEMIS Living Map coloured by class (grey: none of the prompted classes)");
  return io::writePly(path, ply);
}

std::string timingJson(const RunReport& report) {
  nlohmann::ordered_json j;
  j["frames"] = report.frames;
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  for (const std::string& stage :
       {std::string("read"), std::string("register"), std::string("segment"), std::string("segment_wait"),
        std::string("insert"), std::string("fuse"), std::string("mesh"), std::string("constrain"),
        std::string("refine"), std::string("revisit")}) {
    if (report.times.samples(stage).empty()) continue;
    const StageSummary s = report.times.summary(stage);
    stages[stage] = {{"median_ms", s.median_ms}, {"p95_ms", s.p95_ms}, {"max_ms", s.max_ms}};
  }
  const StageSummary total = report.times.summary("total");
  stages["total"] = {{"median_ms", total.median_ms}, {"p95_ms", total.p95_ms}, {"max_ms", total.max_ms}};
  j["stages"] = stages;
  j["finish_ms"] = report.finish_ms;
  j["peak_rss_mb"] = report.peak_rss_mb;
  j["frames_failed"] = report.frames_failed;
  j["points_in_vehicle_path"] = report.points_in_vehicle_path;
  return j.dump(2) + "\n";
}

std::string registrationJson(const RunReport& report) {
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < report.registrations.size(); ++k) {
    const auto& r = report.registrations[k];
    frames.push_back({{"frame", report.registered_frames[k]},
                      {"fallback", r.fallback},
                      {"reason", r.reason},
                      {"iterations", r.icp.iterations},
                      {"correspondences", r.icp.correspondences},
                      {"rms_m", r.icp.rms_m},
                      {"correction_m", r.correction_m},
                      {"correction_deg", r.correction_deg},
                      {"first_distance_m", r.first_distance_m},
                      {"degenerate_directions", r.icp.degenerate_directions},
                      {"source_points", r.source_points},
                      {"ms", r.ms},
                      {"icp_ms", r.icp_ms},
                      {"map_ms", r.map_ms}});
  }
  nlohmann::ordered_json j;
  j["frames"] = frames;
  j["fallbacks"] = report.registration_fallbacks;
  j["degenerate_frames"] = report.degenerate_frames;
  return j.dump(1) + "\n";
}

std::string semanticsJson(const RunReport& report, const RunParams& params) {
  const SemanticRunParams& sem = params.semantics;
  nlohmann::ordered_json j;
  j["vocabulary"] = nlohmann::ordered_json::parse(sem.vocabulary->toJson());
  std::vector<int> prompted;
  for (const semantics::ClassId c : sem.brush->prompts()) prompted.push_back(c);
  j["prompted"] = prompted;
  nlohmann::ordered_json queries = nlohmann::ordered_json::array();
  for (const semantics::QueryRecord& q : sem.brush->history()) {
    std::vector<std::string> names;
    for (const semantics::ClassId c : q.classes) names.emplace_back(sem.vocabulary->name(c));
    queries.push_back({{"text", q.text}, {"classes", names}, {"first_frame", q.first_frame}});
  }
  j["queries"] = queries;
  j["segmenter"] = sem.segmenter->name();
  j["segmenter_settings"] = nlohmann::ordered_json::parse(sem.segmenter_settings_json);
  j["camera"] = report.segmented_camera;
  j["frames_observed"] = report.frames_observed;
  j["frames_unobserved"] = report.frames_unobserved;
  j["frames_not_due"] = report.frames_not_due;
  j["segment_mode"] = sem.realtime ? "realtime" : "offline";
  j["frames_busy"] = report.frames_busy;
  j["frames_late"] = report.frames_late;
  j["segment_every"] = sem.segment_every;
  j["vertices_labelled"] = report.vertices_labelled;
  const mapping::SemanticFusionParams& f = params.mapper.semantics;
  j["fusion"] = {{"sigma_depth_m", f.sigma_depth_m},       {"depth_window_px", f.depth_window_px},
                 {"background_score", f.background_score}, {"confidence_lambda", f.confidence_lambda},
                 {"voxel_prior", f.voxel_prior},           {"geometric_prior", f.geometry.enabled}};
  return j.dump(1) + "\n";
}

Result<RunReport> runPipeline(datasets::Dataset& dataset, const RunParams& params, const fs::path& out,
                              const std::string& config_json, const ProgressFn& progress) {
  if (params.texture_delay < 0) {
    return invalidArgument(fmt::format("texture_delay must be 0 or more frames, not {}", params.texture_delay));
  }
  if (params.texture_revisit < 0) {
    return invalidArgument(fmt::format("texture_revisit must be 0 or more frames, not {}", params.texture_revisit));
  }
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) return ioError(fmt::format("{}: cannot create folder: {}", out.string(), ec.message()));
  if (Status s = writeText(out / "config.json", config_json); !s.isOk()) return s;

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
  bool warned_no_sweep = false;
  std::size_t not_deskewed = 0;
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
    Isometry3d T_W_L = prior;
    const std::size_t frame_index = frame->index;  // the frame may move into the delayed views
    const double frame_stamp_s = frame->stamp_s;
    if (odometry || params.deskew) {
      Stopwatch register_clock;
      if (params.deskew && last_T) {
        const registration::SweepTiming timing{frame->stamp_s, frame->scan_start_s, frame->scan_end_s};
        if (timing.known()) {
          // Motion and period both span the frames since the last mapped one.
          if (!registration::deskewScan(frame->points_L.points, last_T->inverse() * prior,
                                        frame->stamp_s - last_stamp_s, timing)) {
            ++not_deskewed;
            log::warn("frame {}: not deskewed: {:.3f} s since the last frame against a {:.3f} s sweep", frame->index,
                      frame->stamp_s - last_stamp_s, timing.end_s - timing.start_s);
          }
        } else if (!warned_no_sweep) {
          log::warn("{}: no sweep start/end stamps, so scans are not deskewed", dataset.root().string());
          warned_no_sweep = true;
        }
      }
      if (odometry) {
        auto reg = odometry->registerScan(frame->points_L.points, prior, last_T ? static_cast<int>(i - last_i) : 1);
        T_W_L = reg.T_W_L;
        if (reg.fallback) {
          ++report.registration_fallbacks;
          log::warn("frame {}: registration kept the prior pose ({})", frame->index, reg.reason);
        } else if (reg.icp.degenerate_directions > 0) {
          ++report.degenerate_frames;
          log::warn("frame {}: {}", frame->index, reg.reason);
        }
        log::debug(
            "frame {}: registered in {:.1f} ms, {} iterations, {} correspondences, rms {:.3f} m, "
            "correction {:.3f} m {:.3f} deg",
            frame->index, reg.ms, reg.icp.iterations, reg.icp.correspondences, reg.icp.rms_m, reg.correction_m,
            reg.correction_deg);
        report.registrations.push_back(std::move(reg));
        report.registered_frames.push_back(frame->index);
      }
      report.times.add("register", register_clock.elapsedMs());
    }
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
    if (semantic && !live) report.times.add("fuse", stats.fuse_ms);
    report.times.add("mesh", stats.mesh_ms);
    if (params.mapper.constraint.enabled) report.times.add("constrain", stats.constrain_ms);
    report.faces_cut += stats.faces_cut;
    report.points_in_vehicle_path += stats.points_in_vehicle_path;
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
        "frame {}: {} points, {} kept, {} active voxels, {} meshed, insert {:.1f} ms, mesh {:.1f} ms, constrain {:.1f} "
        "ms ({} of {} patch vertices; patch {:.1f}, build {:.1f}, solve {:.1f} ms; {} faces cut)",
        frame_index, stats.points, stats.points_kept, stats.active_voxels, stats.meshed_voxels, stats.insert_ms,
        stats.mesh_ms, stats.constrain_ms, stats.constraint.active_vertices, stats.constraint.patch_vertices,
        stats.constraint.patch_ms, stats.constraint.build_ms, stats.constraint.solve_ms, stats.faces_cut);
    if (params.observer) {
      params.observer({mapper, i + 1, total, frame_index, T_W_L, refined ? &*refined : nullptr, report.times, false});
    }
    if (progress) progress(i + 1, total);
  }
  if (report.frames == 0) return invalidArgument("no frame could be read; nothing written");
  Stopwatch finish_clock;
  mapper.finish();
  report.finish_ms = finish_clock.elapsedMs();
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
  if (not_deskewed > 0) log::warn("{} frames were not deskewed (see above)", not_deskewed);
  report.vertices = mapper.mesh().vertexCount();
  report.faces = mapper.mesh().faceCount();
  SemanticPlyOptions ply_semantics{sem.vocabulary, params.mapper.semantics.confidence_lambda, sem.write_distribution};
  if (Status s = writeMeshPly(mapper.mesh(), out / "mesh.ply", semantic ? &ply_semantics : nullptr); !s.isOk()) {
    return s;
  }
  if (semantic) {
    if (Status s = writeClassColouredPly(mapper.mesh(), *sem.vocabulary, out / "mesh_classes.ply"); !s.isOk()) {
      return s;
    }
    for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) {
      if (mapper.mesh().vertexClass(v) != semantics::kNoClass) ++report.vertices_labelled;
    }
    if (Status s = writeText(out / "semantics.json", semanticsJson(report, params)); !s.isOk()) return s;
    if (report.frames_unobserved > 0) {
      log::warn("{} of {} frames had no semantic observation (see above)", report.frames_unobserved, report.frames);
    }
  }
  if (Status s = writeText(out / "trajectory.txt", trajectory); !s.isOk()) return s;
  if (odometry) {
    if (Status s = writeText(out / "registration.json", registrationJson(report)); !s.isOk()) return s;
  }
  report.peak_rss_mb = peakRssMb();
  if (Status s = writeText(out / "timing.json", timingJson(report)); !s.isOk()) return s;
  return report;
}

}  // namespace artemis::pipeline
