#include "artemis/pipeline/run.hpp"

#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/registration/deskew.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;

namespace {

Status writeText(const fs::path& path, const std::string& text) {
  return io::writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

}  // namespace

Status writeMeshPly(const mapping::SemanticMesh& mesh, const fs::path& path) {
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
  io::PlyData ply = io::makePlyMesh({.xyz = &xyz, .normals = &normals, .rgb = nullptr, .triangles = &triangles});
  ply.comments.push_back("ARTEMIS Living Map: world frame, normals towards the sensor");
  return io::writePly(path, ply);
}

std::string timingJson(const RunReport& report) {
  nlohmann::ordered_json j;
  j["frames"] = report.frames;
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  for (const std::string& stage :
       {std::string("read"), std::string("register"), std::string("insert"), std::string("mesh")}) {
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

Result<RunReport> runPipeline(datasets::Dataset& dataset, const RunParams& params, const fs::path& out,
                              const std::string& config_json, const ProgressFn& progress) {
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

  std::string trajectory;
  std::optional<Isometry3d> last_T;  // pose of the last mapped frame
  std::size_t last_i = 0;
  double last_stamp_s = 0.0;
  dataset.rewind();
  const std::size_t total = dataset.size();
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
    auto frame = dataset.next();
    const double read_ms = frame_clock.elapsedMs();
    if (!frame) {
      if (frame.status().code() == StatusCode::kEndOfData) break;
      log::warn("frame {} skipped: {}", dataset.firstIndex() + i, frame.status().message());
      ++report.frames_failed;
      trajectory += formatRowMajor3x4(prior) + "\n";  // line k stays frame k
      continue;
    }
    Isometry3d T_W_L = prior;
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
    const mapping::FrameStats stats = mapper.integrate(frame->points_L, T_W_L);
    report.times.add("read", read_ms);
    report.times.add("insert", stats.insert_ms);
    report.times.add("mesh", stats.mesh_ms);
    report.times.add("total", frame_clock.elapsedMs());
    trajectory += formatRowMajor3x4(T_W_L) + "\n";
    last_T = T_W_L;
    last_i = i;
    last_stamp_s = frame->stamp_s;
    ++report.frames;
    log::debug("frame {}: {} points, {} kept, {} active voxels, {} meshed, insert {:.1f} ms, mesh {:.1f} ms",
               frame->index, stats.points, stats.points_kept, stats.active_voxels, stats.meshed_voxels, stats.insert_ms,
               stats.mesh_ms);
    if (progress) progress(i + 1, total);
  }
  if (report.frames == 0) return invalidArgument("no frame could be read; nothing written");
  Stopwatch finish_clock;
  mapper.finish();
  report.finish_ms = finish_clock.elapsedMs();
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
  if (Status s = writeMeshPly(mapper.mesh(), out / "mesh.ply"); !s.isOk()) return s;
  if (Status s = writeText(out / "trajectory.txt", trajectory); !s.isOk()) return s;
  if (odometry) {
    if (Status s = writeText(out / "registration.json", registrationJson(report)); !s.isOk()) return s;
  }
  report.peak_rss_mb = peakRssMb();
  if (Status s = writeText(out / "timing.json", timingJson(report)); !s.isOk()) return s;
  return report;
}

}  // namespace artemis::pipeline
