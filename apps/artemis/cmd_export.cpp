// artemis export RUN --format glb|ply|obj [-o FILE]: the run's mesh for other tools. GLB carries
// vertex colours and the custom attributes _CLASS and _CONFIDENCE (three.js, Blender); PLY
// carries class_id, confidence and colour properties (Open3D, CloudCompare, MeshLab); OBJ carries
// colours only.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "artemis/core/log.hpp"
#include "artemis/io/mesh_export.hpp"
#include "artemis/io/ply.hpp"
#include "commands.hpp"
#include "run_mesh.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;

struct ExportFlags {
  std::string run;
  std::string format = "glb";
  std::string output;
  bool class_colours = false;
};

Status writePlyExport(const fs::path& path, const RunMesh& mesh, const std::vector<std::array<std::uint8_t, 3>>& rgb) {
  std::vector<float> xyz;
  xyz.reserve(3 * mesh.positions.size());
  for (const auto& p : mesh.positions) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  std::vector<std::uint8_t> colours;
  colours.reserve(3 * rgb.size());
  for (const auto& c : rgb) colours.insert(colours.end(), c.begin(), c.end());
  std::vector<std::uint32_t> triangles;
  triangles.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
  io::PlyData ply = io::makePlyMesh({.xyz = &xyz, .rgb = rgb.empty() ? nullptr : &colours, .triangles = &triangles});
  ply.comments.push_back("ARTEMIS Living Map export: world frame");
  if (!mesh.class_id.empty()) {
    ply.comments.push_back("class_id: vocabulary id (0: none), confidence: 1 - exp(-lambda W_sem)");
    if (Status s = ply.setScalar("vertex", "class_id", mesh.class_id); !s.isOk()) return s;
    if (!mesh.confidence.empty()) {
      if (Status s = ply.setScalar("vertex", "confidence", mesh.confidence); !s.isOk()) return s;
    }
  }
  return io::writePly(path, ply);
}

int runExport(const ExportFlags& flags) {
  auto mesh = readRunMesh(flags.run);
  if (!mesh) {
    log::error("{}", mesh.status().message());
    return 1;
  }
  fs::path out = flags.output;
  if (out.empty()) {
    std::error_code ec;
    out = fs::is_directory(flags.run, ec) ? fs::path(flags.run) / ("living_map." + flags.format)
                                          : fs::path(flags.run).replace_extension(flags.format);
    if (fs::equivalent(out, flags.run, ec)) {
      log::error("{}: give -o: the export would replace its own input", out.string());
      return 1;
    }
  }
  // Colours: the texture, or with --class-colours (or an untextured run with classes) the class
  // colours, so that the file shows something beyond grey.
  std::vector<std::array<std::uint8_t, 3>> rgb = mesh->rgb;
  if (flags.class_colours || (rgb.empty() && !mesh->class_id.empty())) {
    if (mesh->class_id.empty()) {
      log::error("{}: --class-colours: the mesh has no classes", flags.run);
      return 1;
    }
    rgb.resize(mesh->class_id.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = mesh->vocabulary.colour(mesh->class_id[i]);
  }
  const io::ExportMesh view{mesh->positions, mesh->triangles, rgb, mesh->class_id, mesh->confidence};
  Status s = flags.format == "glb"   ? io::writeGlb(out, view)
             : flags.format == "obj" ? io::writeObj(out, view)
                                     : writePlyExport(out, *mesh, rgb);
  if (!s.isOk()) {
    log::error("{}", s.message());
    return 1;
  }
  fmt::print("{}: {} vertices, {} faces{}{}\n", out.string(), mesh->positions.size(), mesh->triangles.size(),
             rgb.empty() ? "" : ", colours", mesh->class_id.empty() || flags.format == "obj" ? "" : ", classes");
  return 0;
}

}  // namespace

void addExportCommand(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<ExportFlags>();
  auto* cmd =
      app.add_subcommand("export",
                         "A run's mesh for other tools: GLB (vertex colours, _CLASS and _CONFIDENCE attributes), "
                         "PLY (class_id, confidence, colours) or OBJ (colours)");
  cmd->add_option("RUN", flags->run, "Run folder of artemis run (its mesh.ply and semantics.json), or a mesh PLY")
      ->required();
  cmd->add_option("--format,-f", flags->format, "glb, ply or obj")
      ->capture_default_str()
      ->check(CLI::IsMember({"glb", "ply", "obj"}));
  cmd->add_option("-o,--output", flags->output, "File to write (default: living_map.<format> in the run folder)");
  cmd->add_flag("--class-colours", flags->class_colours,
                "Colour vertices by class instead of texture (the default for a run without texture)");
  cmd->callback([flags, &exit_code] { exit_code = runExport(*flags); });
}

}  // namespace artemis::cli
