#pragma once
// The live viewer of `artemis run --viewer`: started before the first frame, it shows the map as
// it grows.

#include <memory>

#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"
#include "run_flags.hpp"
#include "run_semantics.hpp"
#include "viewer/live.hpp"
#include "viewer/scene.hpp"
#include "viewer/server.hpp"

namespace artemis::cli {

struct LiveViewer {
  viewer::Scene scene;
  std::unique_ptr<viewer::Server> server;  // serves `scene`
  std::unique_ptr<viewer::LivePublisher> publisher;
};

// Starts the server (and prints its address) and sets flags.params.observer to publish every
// frame into the scene. `semantic`: the run's semantics, nullptr without; it, and the viewer
// returned, must outlive the run.
Result<std::unique_ptr<LiveViewer>> startLiveViewer(RunFlags& flags, const datasets::Dataset& dataset,
                                                    SemanticSetup* semantic);

}  // namespace artemis::cli
