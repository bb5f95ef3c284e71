#include "artemis/pipeline/run.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <string>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"

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
  for (const std::string& stage : {std::string("read"), std::string("insert"), std::string("mesh")}) {
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

Result<RunReport> runPipeline(datasets::Dataset& dataset, const RunParams& params, const fs::path& out,
                              const std::string& config_json, const ProgressFn& progress) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) return ioError(fmt::format("{}: cannot create folder: {}", out.string(), ec.message()));
  if (Status s = writeText(out / "config.json", config_json); !s.isOk()) return s;

  RunReport report;
  mapping::Mapper mapper(params.mapper);
  std::string trajectory;
  dataset.rewind();
  const std::size_t total = dataset.size();
  for (std::size_t i = 0; i < total; ++i) {
    Stopwatch frame_clock;
    auto frame = dataset.next();
    const double read_ms = frame_clock.elapsedMs();
    if (!frame) {
      if (frame.status().code() == StatusCode::kEndOfData) break;
      log::warn("frame {} skipped: {}", dataset.firstIndex() + i, frame.status().message());
      ++report.frames_failed;
      trajectory += formatRowMajor3x4(dataset.pose(i)) + "\n";  // line k stays frame k
      continue;
    }
    const mapping::FrameStats stats = mapper.integrate(frame->points_L, frame->T_W_L);
    report.times.add("read", read_ms);
    report.times.add("insert", stats.insert_ms);
    report.times.add("mesh", stats.mesh_ms);
    report.times.add("total", frame_clock.elapsedMs());
    trajectory += formatRowMajor3x4(frame->T_W_L) + "\n";
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
  report.vertices = mapper.mesh().vertexCount();
  report.faces = mapper.mesh().faceCount();
  if (Status s = writeMeshPly(mapper.mesh(), out / "mesh.ply"); !s.isOk()) return s;
  if (Status s = writeText(out / "trajectory.txt", trajectory); !s.isOk()) return s;
  report.peak_rss_mb = peakRssMb();
  if (Status s = writeText(out / "timing.json", timingJson(report)); !s.isOk()) return s;
  return report;
}

}  // namespace artemis::pipeline
