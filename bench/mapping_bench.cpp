// The geometry pipeline on the real KITTI drive (frames 0-49 with the reference poses): per-stage
// time per frame (insert, carve, mesh, constrain; median and p95; frames 0-9 against 40-49 for
// insert + mesh), the CPU time a frame takes on all threads, peak memory, and
// accuracy against the reference cloud built from the same scans and poses, beside Open3D's
// Poisson reconstruction (the paper's "Poi" baseline) scored by the same evaluator.
//
//   build/bench/mapping_bench [--no-poisson] [--threads N] [--texture]
// --texture: the whole pipeline as `artemis run` maps the drive by default, with the camera images
// and texture refinement (every 5th view held out, as `artemis eval texture` scores it).
// Data: $ARTEMIS_DATA_DIR/kitti_raw (default ../shared/data/kitti_raw).
#include <fmt/format.h>

#include <unistd.h>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/dataset_summary.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/geometry.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/pipeline/timing.hpp"

namespace {

namespace fs = std::filesystem;
using namespace artemis;

fs::path dataDir() {
  const char* env = std::getenv("ARTEMIS_DATA_DIR");
  return env != nullptr && *env != '\0' ? fs::path(env) : fs::path("../shared/data");
}

void printScores(const char* name, const std::vector<eval::GeometryScore>& scores) {
  for (const auto& s : scores) {
    fmt::print("  {:<10} tau {:.2f} m: precision {:.4f}  recall {:.4f}  F1 {:.4f}\n", name, s.tau_m, s.precision,
               s.recall, s.f1);
  }
}

unsigned hardwareThreads() {
  return std::max(1u, std::thread::hardware_concurrency());
}

Result<eval::MeshArrays> meshOf(const fs::path& ply) {
  return eval::readMeshArrays(ply);
}

}  // namespace

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  bool poisson = true;
  int threads = 0;
  bool texture = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--no-poisson") poisson = false;
    if (arg == "--texture") texture = true;
    if (arg == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
  }
  const fs::path raw = dataDir() / "kitti_raw";
  const fs::path poses = raw / "reference_poses.txt";
  if (!fs::exists(poses)) {
    fmt::print(stderr, "{} not found: set ARTEMIS_DATA_DIR to the folder holding kitti_raw/\n", poses.string());
    return 1;
  }
  datasets::DatasetOptions options;
  options.frames = {0, 50};
  options.load_images = texture;
  auto dataset = datasets::openDataset(raw, datasets::DatasetFormat::kAuto, options);
  if (!dataset) {
    fmt::print(stderr, "{}\n", dataset.status().toString());
    return 1;
  }
  auto T_W_L = datasets::readPoseFile(poses);
  if (!T_W_L || !(*dataset)->setPoses(*T_W_L).isOk()) {
    fmt::print(stderr, "{}: cannot use these poses\n", poses.string());
    return 1;
  }
  const fs::path out = fs::temp_directory_path() / fmt::format("artemis-mapping-bench-{}", ::getpid());
  pipeline::RunParams params;
  params.mapper.threads = threads;
  params.texture = texture;
  params.texture_holdout = texture ? 5 : 0;
  Stopwatch clock;
  auto report = pipeline::runPipeline(**dataset, params, out, "{}\n");
  if (!report) {
    fmt::print(stderr, "{}\n", report.status().toString());
    return 1;
  }
  const double run_s = clock.elapsedS();
  fmt::print("ARTEMIS on kitti_raw frames 0-49 ({} frames, reference poses{}), {} threads\n", report->frames,
             texture ? ", texture on, every 5th view held out" : "",
             threads == 0 ? std::string("all") : std::to_string(threads));
  const auto row = [&](const char* stage, std::size_t a, std::size_t b) {
    const auto s = report->times.summary(stage, a, b);
    fmt::print("  {:<8} median {:6.1f} ms  p95 {:6.1f} ms  max {:6.1f} ms\n", stage, s.median_ms, s.p95_ms, s.max_ms);
  };
  // Geometry = insert + mesh per frame.
  for (std::size_t i = 0; i < report->frames; ++i) {
    report->times.add("geometry", report->times.samples("insert")[i] + report->times.samples("mesh")[i]);
  }
  for (const char* stage : {"read", "insert", "carve", "mesh", "constrain", "refine", "revisit", "geometry", "total"}) {
    if (!report->times.samples(stage).empty()) row(stage, 0, report->frames);
  }
  // The work of a frame on all threads: on N cores no frame can take less than this over N.
  const auto cpu = report->times.summary("cpu");
  fmt::print(
      "  cpu      median {:6.1f} ms  p95 {:6.1f} ms  (all threads' time while a frame is mapped; over {} cores: "
      "{:.1f} ms)\n",
      cpu.median_ms, cpu.p95_ms, hardwareThreads(), cpu.median_ms / hardwareThreads());
  fmt::print("  frames 0-9 vs 40-49 (geometry): median {:.1f} vs {:.1f} ms, p95 {:.1f} vs {:.1f} ms\n",
             report->times.summary("geometry", 0, 10).median_ms, report->times.summary("geometry", 40, 50).median_ms,
             report->times.summary("geometry", 0, 10).p95_ms, report->times.summary("geometry", 40, 50).p95_ms);
  fmt::print(
      "  final meshing {:.0f} ms; {} vertices, {} faces; peak memory {:.0f} MB, {} page faults; {:.1f} s in all\n",
      report->finish_ms, report->vertices, report->faces, report->peak_rss_mb, pipeline::pageFaults(), run_s);

  // The reference: every range-gated scan with the same poses, 0.05 m voxels (DESIGN.md).
  const auto reference_cloud = datasets::aggregateScans(**dataset, 0.05);
  eval::Reference reference;
  reference.geometry.vertices = reference_cloud.cloud_W.points;
  auto mesh = meshOf(out / "mesh.ply");
  if (!mesh) {
    fmt::print(stderr, "{}\n", mesh.status().toString());
    return 1;
  }
  auto ours = eval::evaluateGeometry(*mesh, reference, eval::GeometryParams{});
  if (!ours) {
    fmt::print(stderr, "{}\n", ours.status().toString());
    return 1;
  }
  fmt::print("Accuracy against the reference cloud ({} points):\n", reference_cloud.cloud_W.size());
  printScores("ARTEMIS", *ours);

  if (poisson) {
    // Open3D's screened Poisson on the same reference cloud, normals towards the trajectory.
    const fs::path cloud_ply = out / "reference.ply";
    io::PlyData ply;
    std::vector<float> x, y, z;
    for (const auto& p : reference_cloud.cloud_W.points) {
      x.push_back(p.x());
      y.push_back(p.y());
      z.push_back(p.z());
    }
    (void)ply.setScalar("vertex", "x", x);
    (void)ply.setScalar("vertex", "y", y);
    (void)ply.setScalar("vertex", "z", z);
    if (!io::writePly(cloud_ply, ply).isOk()) return 1;
    const fs::path script = fs::path(ARTEMIS_SOURCE_DIR) / "bench" / "poisson_baseline.py";
    const std::string command =
        fmt::format("/usr/bin/python3 {} --cloud {} --trajectory {} --out {}", script.string(), cloud_ply.string(),
                    (out / "trajectory.txt").string(), (out / "poisson.ply").string());
    std::fflush(stdout);  // our lines before the script's
    Stopwatch poisson_clock;
    if (std::system(command.c_str()) != 0) {
      fmt::print(stderr, "Poisson baseline failed: {}\n", command);
    } else {
      const double poisson_s = poisson_clock.elapsedS();
      auto poisson_mesh = meshOf(out / "poisson.ply");
      if (poisson_mesh) {
        auto theirs = eval::evaluateGeometry(*poisson_mesh, reference, eval::GeometryParams{});
        if (theirs) {
          printScores("Poisson", *theirs);
          fmt::print("  Poisson took {:.1f} s for the whole sequence (offline, all points at once)\n", poisson_s);
        }
      }
    }
  }
  std::error_code ec;
  fs::remove_all(out, ec);
  return 0;
}
