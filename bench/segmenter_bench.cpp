// The dense segmenter's time per frame on the real drive, apart from the mapping pipeline: the
// shared ENet (ARTEMIS_MODEL_DIR, default ../shared/models) on KITTI drive 0013's images
// (ARTEMIS_DATA_DIR, default ../shared/data), 1242 x 375 padded to 1248 x 376, on 2 threads
// unless --threads N; --width W also times the image scaled to W (aspect kept). Prints the model's
// load time and per-frame median and p95 of the whole segment() (forward pass, softmax, classes)
// for the prompt "car", and peak memory.
//
// Then what dense semantics cost the mapping pipeline itself, without the network's CPU load: the
// network's observations of frames 0-49 are computed first, and artemis run's pipeline (reference
// poses, texture on, as artemis run) maps the frames twice without semantics and twice with those observations
// replayed, alternately; per-stage median / p95 of each run. --no-pipeline skips this part.
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/png.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/semantics/active_brush.hpp"
#include "artemis/semantics/dnn_segmenter.hpp"
#include "bench_stats.hpp"

namespace {

namespace fs = std::filesystem;
using namespace artemis;

fs::path envDir(const char* name, const char* fallback) {
  const char* env = std::getenv(name);
  return env != nullptr && *env != '\0' ? fs::path(env) : fs::path(fallback);
}

int timeAtWidth(const fs::path& model, const fs::path& images, int threads, int width, int frames) {
  const semantics::Vocabulary& vocabulary = semantics::Vocabulary::semanticKitti();
  auto config =
      semantics::DenseModelConfig::load(fs::path(ARTEMIS_SOURCE_DIR) / "data/models/enet-cityscapes.json", vocabulary);
  if (!config) {
    fmt::print(stderr, "{}\n", config.status().message());
    return 1;
  }
  config->input.resize_width = width;
  Stopwatch load_clock;
  auto segmenter = semantics::DnnSegmenter::open(model, *config, threads);
  if (!segmenter) {
    fmt::print(stderr, "{}\n", segmenter.status().message());
    return 1;
  }
  const double load_ms = load_clock.elapsedMs();
  const std::vector<semantics::ClassId> prompts{vocabulary.findByName("car")->id};
  std::vector<double> ms;
  for (int i = 0; i < frames; ++i) {
    auto image = io::readPng8(images / fmt::format("{:010d}.png", i), 3);
    if (!image) {
      fmt::print(stderr, "{}\n", image.status().message());
      return 1;
    }
    CameraView view;
    view.image = std::move(*image);
    Stopwatch clock;
    auto obs = (*segmenter)->segment({static_cast<std::size_t>(i), &view}, prompts);
    if (!obs) {
      fmt::print(stderr, "{}\n", obs.status().message());
      return 1;
    }
    if (i > 0) ms.push_back(clock.elapsedMs());  // the first pass loads the network for the image's size
  }
  const bench::Percentiles p = bench::percentiles(ms);
  fmt::print(
      "dnn segmenter, {} threads, input {}: load {:.0f} ms; per frame median {:.1f} ms, p95 {:.1f} ms ({} frames)\n",
      threads, width > 0 ? fmt::format("scaled to width {}", width) : std::string("1248x376 (padded)"), load_ms,
      p.median, p.p95, ms.size());
  return 0;
}

// A segmenter that hands out observations computed before (by frame index).
class Replay final : public semantics::Segmenter {
 public:
  explicit Replay(std::vector<semantics::SemanticObservation> observations) : observations_(std::move(observations)) {}
  [[nodiscard]] std::string name() const override { return "replay"; }
  Result<semantics::SemanticObservation> segment(const semantics::SegmentRequest& request,
                                                 std::span<const semantics::ClassId> /*prompts*/) override {
    if (request.frame_index >= observations_.size()) return notFound("no observation kept");
    return observations_[request.frame_index];
  }

 private:
  std::vector<semantics::SemanticObservation> observations_;
};

int pipelineCost(const fs::path& data, const fs::path& model, int threads) {
  const semantics::Vocabulary& vocabulary = semantics::Vocabulary::semanticKitti();
  auto config =
      semantics::DenseModelConfig::load(fs::path(ARTEMIS_SOURCE_DIR) / "data/models/enet-cityscapes.json", vocabulary);
  auto segmenter = config ? semantics::DnnSegmenter::open(model, *config, threads)
                          : Result<std::unique_ptr<semantics::DnnSegmenter>>(config.status());
  const fs::path raw = data / "kitti_raw";
  datasets::DatasetOptions options;
  options.frames = {0, 50};
  auto dataset = datasets::openDataset(raw, datasets::DatasetFormat::kAuto, options);
  auto poses = datasets::readPoseFile(raw / "reference_poses.txt");
  if (!segmenter || !dataset || !poses || !(*dataset)->setPoses(*poses).isOk()) {
    fmt::print(stderr, "pipeline cost: cannot set up the model, the drive or its poses\n");
    return 1;
  }
  const semantics::ClassId car = vocabulary.findByName("car")->id;
  const std::vector<semantics::ClassId> prompts{car};
  std::vector<semantics::SemanticObservation> observations;
  for (std::size_t i = 0; i < (*dataset)->size(); ++i) {
    auto frame = (*dataset)->frame(i);
    if (!frame || frame->cameras.empty()) return 1;
    auto obs = (*segmenter)->segment({frame->index, &frame->cameras.front()}, prompts);
    if (!obs) return 1;
    observations.push_back(std::move(*obs));
  }
  Replay replay(std::move(observations));
  const fs::path out = fs::temp_directory_path() / fmt::format("artemis-segmenter-bench-{}", ::getpid());
  for (int round = 0; round < 4; ++round) {
    const bool semantic = round % 2 == 1;
    semantics::ActiveBrush brush;
    brush.add("cars", prompts);
    pipeline::RunParams params;
    params.mapper.threads = threads;
    params.pose_refinement = false;
    params.texture = true;  // as artemis run does on a recording with a camera
    if (semantic) {
      params.semantics.segmenter = &replay;
      params.semantics.brush = &brush;
      params.semantics.vocabulary = &vocabulary;
    }
    auto report = pipeline::runPipeline(**dataset, params, out, "{}\n");
    if (!report) {
      fmt::print(stderr, "{}\n", report.status().toString());
      return 1;
    }
    std::string line;
    for (const char* stage : {"insert", "fuse", "mesh", "constrain", "refine", "revisit", "total"}) {
      if (report->times.samples(stage).empty()) continue;
      const auto t = report->times.summary(stage);
      line += fmt::format("  {} {:.1f} / {:.1f}", stage, t.median_ms, t.p95_ms);
    }
    fmt::print("pipeline {} (median / p95 ms):{}\n", semantic ? "with dense semantics" : "without semantics   ", line);
  }
  std::error_code ec;
  fs::remove_all(out, ec);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  int threads = 2;
  int width = 0;
  int frames = 20;
  bool pipeline_cost = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--no-pipeline") pipeline_cost = false;
    if (arg == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
    if (arg == "--width" && i + 1 < argc) width = std::atoi(argv[++i]);
    if (arg == "--frames" && i + 1 < argc) frames = std::atoi(argv[++i]);
  }
  const fs::path model = envDir("ARTEMIS_MODEL_DIR", "../shared/models") / "enet-cityscapes/model.net";
  const fs::path images =
      envDir("ARTEMIS_DATA_DIR", "../shared/data") / "kitti_raw/2011_09_26/2011_09_26_drive_0013_sync/image_02/data";
  if (!fs::exists(model) || !fs::exists(images)) {
    fmt::print(stderr, "{} or {} not found: set ARTEMIS_MODEL_DIR and ARTEMIS_DATA_DIR\n", model.string(),
               images.string());
    return 1;
  }
  if (int rc = timeAtWidth(model, images, threads, 0, frames); rc != 0) return rc;
  if (width > 0) {
    if (int rc = timeAtWidth(model, images, threads, width, frames); rc != 0) return rc;
  }
  if (pipeline_cost) {
    if (int rc = pipelineCost(envDir("ARTEMIS_DATA_DIR", "../shared/data"), model, threads); rc != 0) return rc;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  fmt::print("peak memory {:.0f} MB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
  return 0;
}
