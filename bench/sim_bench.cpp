// Speed of the street simulator on this machine: building the scene, one LiDAR sweep, one camera
// frame, and a whole 100-frame sequence written to disk (the figure the simulator is held to:
// under 1 s a frame on 2 cores).
//
//   build/bench/sim_bench                      all of them
//   build/bench/sim_bench --benchmark_filter=Sequence
#include <benchmark/benchmark.h>

#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <numeric>
#include <string>

#include "artemis/sim/simulator.hpp"
#include "artemis/sim/writer.hpp"

namespace {

using artemis::sim::SimParams;
using artemis::sim::Simulator;

const Simulator& sharedSim() {
  static const Simulator sim([] {
    SimParams p;
    p.frames = 100;
    return p;
  }());
  return sim;
}

void BM_SceneBuild(benchmark::State& state) {
  for (auto _ : state) {
    const Simulator sim(SimParams{});
    benchmark::DoNotOptimize(sim.scene().mesh.faceCount());
  }
  state.counters["triangles"] = static_cast<double>(sharedSim().scene().mesh.faceCount());
}
BENCHMARK(BM_SceneBuild)->Unit(benchmark::kMillisecond);

void BM_LidarScan(benchmark::State& state) {
  const Simulator& sim = sharedSim();
  int frame = 0;
  std::size_t points = 0;
  for (auto _ : state) {
    const auto scan = sim.scan(frame++ % sim.frames());
    points = scan.points_L.size();
    benchmark::DoNotOptimize(points);
  }
  state.counters["points"] = static_cast<double>(points);
}
BENCHMARK(BM_LidarScan)->Unit(benchmark::kMillisecond);

void BM_CameraRender(benchmark::State& state) {
  const Simulator& sim = sharedSim();
  int frame = 0;
  for (auto _ : state) {
    const auto images = sim.render(frame++ % sim.frames());
    benchmark::DoNotOptimize(images.rgb.data().data());
  }
}
BENCHMARK(BM_CameraRender)->Unit(benchmark::kMillisecond);

// The whole job: scene, 100 frames simulated and written (scans, labels, four PNGs a frame, mesh).
void BM_Sequence100(benchmark::State& state) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("artemis-sim-bench-" + std::to_string(::getpid()));
  SimParams params;
  params.frames = 100;
  for (auto _ : state) {
    std::filesystem::remove_all(out);
    auto report = artemis::sim::writeSequence(params, out);
    if (!report) {
      state.SkipWithError(report.status().toString().c_str());
      break;
    }
    const auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    state.counters["lidar_ms"] = median(report->lidar_ms);
    state.counters["camera_ms"] = median(report->camera_ms);
    state.counters["write_ms"] = median(report->write_ms);
    state.counters["scene_ms"] = report->scene_ms;
  }
  // Per frame: the benchmark's time divided by the frame count.
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * params.frames);
  std::filesystem::remove_all(out);
}
BENCHMARK(BM_Sequence100)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
