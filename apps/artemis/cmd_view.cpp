// artemis view RUN: the browser viewer on a finished run: the textured mesh, class colours,
// the trajectory, and queries highlighted on the surface.

#include <memory>
#include <string>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "commands.hpp"
#include "flag_checks.hpp"
#include "run_folder.hpp"
#include "run_mesh.hpp"
#include "viewer/flags.hpp"
#include "viewer/scene.hpp"
#include "viewer/server.hpp"
#include "viewer/session.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;

struct ViewFlags {
  std::string run;
  ViewerFlags viewer;
  double exit_after_s = -1.0;
};

int runView(const ViewFlags& flags) {
  Stopwatch clock;
  auto mesh = readRunMesh(flags.run);
  if (!mesh) {
    log::error("{}", mesh.status().message());
    return 1;
  }
  std::error_code ec;
  const bool folder = fs::is_directory(flags.run, ec);
  const fs::path run_dir = folder ? fs::path(flags.run) : fs::path(flags.run).parent_path();
  viewer::Scene scene;
  scene.update(viewer::meshBlocks(mesh->positions, mesh->triangles, mesh->rgb, mesh->class_id, flags.viewer.block_m));
  const fs::path absolute = fs::absolute(flags.run).lexically_normal();
  scene.setInfo("title", (absolute.has_filename() ? absolute : absolute.parent_path()).filename().string());
  scene.setInfo("textured", !mesh->rgb.empty());
  scene.setInfo("classes", viewer::classesJson(mesh->vocabulary, mesh->prompted));
  scene.setInfo("vocabulary", viewer::vocabularyJson(mesh->vocabulary));
  if (folder) {
    if (auto trajectory = datasets::readPoseFile(run_dir / "trajectory.txt"); trajectory) {
      for (const Isometry3d& T : *trajectory) scene.appendTrajectory(T.translation());
    }
    // The run's timings, as the live viewer showed them.
    if (fs::exists(run_dir / "timing.json", ec)) {
      if (auto timing = readJsonFile(run_dir / "timing.json", ""); timing && timing->is_object()) {
        const auto frames = timing->value("frames", 0);
        scene.setInfo("status", {{"done", frames},
                                 {"total", frames},
                                 {"running", false},
                                 {"stages", timing->value("stages", nlohmann::json::object())}});
      }
    }
  }
  auto query = viewer::makeQueryFn(mesh->vocabulary, mesh->prompted);
  if (!query) {
    log::error("{}", query.status().message());
    return 1;
  }
  viewer::ServerParams params = flags.viewer.serverParams();
  params.run_dir = folder ? run_dir : fs::path();
  viewer::Server server(scene, params, *query);
  auto port = server.start();
  if (!port) {
    log::error("{}", port.status().message());
    return 1;
  }
  log::info("{}: {} vertices, {} faces in {} blocks, loaded in {:.1f} s", flags.run, mesh->positions.size(),
            mesh->triangles.size(), scene.infoJson()["blocks"].get<std::size_t>(), clock.elapsedS());
  viewer::announce(server, "Ctrl-C to stop");
  viewer::waitForInterrupt(flags.exit_after_s);
  server.stop();
  return 0;
}

}  // namespace

void addViewCommand(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<ViewFlags>();
  auto* cmd =
      app.add_subcommand("view",
                         "Browser viewer of a run: the textured mesh, class colours, the trajectory, and a query box "
                         "that highlights the classes it names. Serves http://127.0.0.1:PORT/ until Ctrl-C.");
  cmd->add_option("RUN", flags->run,
                  "Run folder of artemis run (mesh.ply, semantics.json, trajectory.txt), or a mesh PLY")
      ->required();
  addViewerFlags(*cmd, flags->viewer, "");
  cmd->add_option("--exit-after", flags->exit_after_s, "Stop serving after this many seconds (default: at Ctrl-C)")
      ->check(within(0.0, 1e7));
  cmd->callback([flags, &exit_code] { exit_code = runView(*flags); });
}

}  // namespace artemis::cli
