// The dense segmenter's time per frame on the real drive, apart from the mapping pipeline: the
// shared ENet (ARTEMIS_MODEL_DIR, default ../shared/models) on KITTI drive 0013's images
// (ARTEMIS_DATA_DIR, default ../shared/data), 1242 x 375 padded to 1248 x 376, on 2 threads
// unless --threads N; --width W also times the image scaled to W (aspect kept). Prints the model's
// load time and per-frame median and p95 of the whole segment() (forward pass, softmax, classes)
// for the prompt "car", and peak memory.
#include <fmt/format.h>
#include <sys/resource.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/timer.hpp"
#include "artemis/io/png.hpp"
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

}  // namespace

int main(int argc, char** argv) {
  int threads = 2;
  int width = 0;
  int frames = 20;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
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
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  fmt::print("peak memory {:.0f} MB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
  return 0;
}
