#include "run_live_viewer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "viewer/session.hpp"

namespace artemis::cli {

namespace fs = std::filesystem;

Result<std::unique_ptr<LiveViewer>> startLiveViewer(RunFlags& flags, const datasets::Dataset& dataset,
                                                    SemanticSetup* semantic) {
  auto live = std::make_unique<LiveViewer>();
  viewer::Scene& scene = live->scene;
  semantics::ActiveBrush* brush = semantic != nullptr ? &semantic->brush : nullptr;
  const semantics::Vocabulary& vocabulary =
      semantic != nullptr ? semantic->vocabulary : semantics::Vocabulary::semanticKitti();
  const fs::path out_dir = fs::absolute(flags.out).lexically_normal();
  scene.setInfo("title", (out_dir.has_filename() ? out_dir : out_dir.parent_path()).filename().string());
  scene.setInfo("textured", flags.params.texture);
  scene.setInfo("vocabulary", viewer::vocabularyJson(vocabulary));
  scene.setInfo("classes", viewer::classesJson(
                               vocabulary, brush != nullptr ? brush->prompts() : std::vector<semantics::ClassId>{}));
  scene.setInfo("status", viewer::statusJson({}, 0, dataset.size(), dataset.firstIndex(), true));
  auto query = viewer::makeQueryFn(vocabulary, {}, brush);
  if (!query) return query.status();
  viewer::ServerParams server_params = flags.viewer_flags.serverParams();
  server_params.run_dir = flags.out;
  live->server = std::make_unique<viewer::Server>(scene, server_params, *query);
  auto port = live->server->start();
  if (!port) return port.status();
  const auto block_voxels = static_cast<std::int32_t>(
      std::max(1.0, std::round(flags.viewer_flags.block_m / flags.params.mapper.voxels.voxel_size_m)));
  live->publisher = std::make_unique<viewer::LivePublisher>(scene, block_voxels);
  flags.params.observer = [live_viewer = live.get(), brush,
                           vocabulary = &vocabulary](const pipeline::FrameUpdate& update) {
    if (brush != nullptr) live_viewer->scene.setInfo("classes", viewer::classesJson(*vocabulary, brush->prompts()));
    live_viewer->publisher->onFrame(update);
  };
  viewer::announce(*live->server, "live");
  return live;
}

}  // namespace artemis::cli
