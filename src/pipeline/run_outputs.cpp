#include "run_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artemis/core/allocator.hpp"
#include "artemis/core/colour.hpp"
#include "artemis/core/log.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;

Status writeText(const fs::path& path, const std::string& text) {
  return io::writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

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
        std::string("insert"), std::string("carve"), std::string("fuse"), std::string("mesh"), std::string("constrain"),
        std::string("refine"), std::string("revisit"), std::string("evict")}) {
    if (report.times.samples(stage).empty()) continue;
    const StageSummary s = report.times.summary(stage);
    stages[stage] = {{"median_ms", s.median_ms}, {"p95_ms", s.p95_ms}, {"max_ms", s.max_ms}};
  }
  const StageSummary total = report.times.summary("total");
  stages["total"] = {{"median_ms", total.median_ms}, {"p95_ms", total.p95_ms}, {"max_ms", total.max_ms}};
  j["stages"] = stages;
  const StageSummary cpu = report.times.summary("cpu");
  j["cpu"] = {{"median_ms", cpu.median_ms}, {"p95_ms", cpu.p95_ms}, {"max_ms", cpu.max_ms}};
  j["finish_ms"] = report.finish_ms;
  j["peak_rss_mb"] = report.peak_rss_mb;
  j["page_faults"] = report.page_faults;
  // See core/allocator.hpp.
  j["allocator"] = !allocatorTuned() ? "system" : allocatorHugePages() ? "glibc, tuned, huge pages" : "glibc, tuned";
  j["frames_failed"] = report.frames_failed;
  j["points_in_vehicle_path"] = report.points_in_vehicle_path;
  j["points_carved"] = report.points_carved;
  j["holes_filled"] = report.holes_filled;
  j["tiles"] = {{"finished_during_run", report.tiles_finished},
                {"reloaded", report.tiles_reloaded},
                {"in_memory_at_last_look", report.tiles_in_memory},
                {"files", report.tiles_written},
                {"points_in_finished_tiles", report.points_in_finished_tiles},
                {"dangling_faces", report.dangling_faces},
                {"repeated_faces", report.repeated_faces}};
  j["checkpoints"] = {{"written", report.checkpoints},
                      {"last_mb", report.checkpoint_mb},
                      {"max_ms", report.checkpoint_max_ms},
                      {"resumed_at_frame", report.resumed_at}};
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
  j["fusion"] = {{"sigma_depth_m", f.sigma_depth_m},
                 {"depth_window_px", f.depth_window_px},
                 {"background_score", f.background_score},
                 {"confidence_lambda", f.confidence_lambda},
                 {"voxel_prior", f.voxel_prior},
                 {"geometric_prior", f.geometry.enabled},
                 {"silhouette_radius_px", f.geometry.silhouettes.radius_px}};
  return j.dump(1) + "\n";
}
Status writeRunOutputs(const mapping::Mapper& mapper, const RunParams& params, const std::string& trajectory,
                       bool registered, const fs::path& out, RunReport& report, bool meshes_written) {
  const SemanticRunParams& sem = params.semantics;
  const bool semantic = sem.segmenter != nullptr;
  SemanticPlyOptions ply_semantics{sem.vocabulary, params.mapper.semantics.confidence_lambda, sem.write_distribution};
  if (!meshes_written) {
    if (Status s = writeMeshPly(mapper.mesh(), out / "mesh.ply", semantic ? &ply_semantics : nullptr); !s.isOk()) {
      return s;
    }
  }
  if (semantic) {
    if (!meshes_written) {
      if (Status s = writeClassColouredPly(mapper.mesh(), *sem.vocabulary, out / "mesh_classes.ply"); !s.isOk()) {
        return s;
      }
      for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) {
        if (mapper.mesh().vertexClass(v) != semantics::kNoClass) ++report.vertices_labelled;
      }
    }
    if (Status s = writeText(out / "semantics.json", semanticsJson(report, params)); !s.isOk()) return s;
    if (report.frames_unobserved > 0) {
      log::warn("{} of {} frames had no semantic observation (see above)", report.frames_unobserved, report.frames);
    }
  }
  if (Status s = writeText(out / "trajectory.txt", trajectory); !s.isOk()) return s;
  if (registered) {
    if (Status s = writeText(out / "registration.json", registrationJson(report)); !s.isOk()) return s;
  }
  report.peak_rss_mb = peakRssMb();
  report.page_faults = pageFaults();
  return writeText(out / "timing.json", timingJson(report));
}

}  // namespace artemis::pipeline
