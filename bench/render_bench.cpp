// The rasterizer's time for a KITTI-sized picture (1242 x 375) of the simulated street's
// ground-truth surface (~620k triangles), drawn whole (no culling) from camera poses along the
// drive, with and without vertex colours; median and p95 over the poses.
//
//   build/bench/render_bench [--frames N]
#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/render/rasterizer.hpp"
#include "artemis/sim/simulator.hpp"
#include "bench_stats.hpp"

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  using namespace artemis;
  int frames = 100;
  if (argc == 3 && std::strcmp(argv[1], "--frames") == 0) frames = std::atoi(argv[2]);
  if (frames < 1) {
    fmt::print(stderr, "usage: render_bench [--frames N]\n");
    return 2;
  }
  sim::SimParams params;
  params.frames = frames;
  const sim::Simulator sim(params);
  const auto& scene = sim.scene().mesh;
  const Isometry3d T_W_S = sim.T_S_W().inverse();
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> colours;
  for (const auto& v : scene.vertices) {
    positions.push_back((T_W_S * v.cast<double>()).cast<float>());
    colours.emplace_back(0.5f, 0.5f, 0.5f);
  }
  std::vector<double> plain_ms, colour_ms;
  std::size_t covered = 0;
  for (int k = 0; k < frames; k += std::max(1, frames / 20)) {
    render::View view;
    view.camera = sim.camera();
    view.T_W_C = sim.T_W_L(k) * sim.T_L_C();
    Stopwatch clock;
    const auto pic = render::rasterize({positions, scene.triangles, {}}, view);
    plain_ms.push_back(clock.elapsedMs());
    clock.reset();
    const auto coloured = render::rasterize({positions, scene.triangles, colours}, view);
    colour_ms.push_back(clock.elapsedMs());
    for (const auto f : pic.face) covered += f != render::kNoFace ? 1 : 0;
  }
  const auto p = bench::percentiles(plain_ms);
  const auto c = bench::percentiles(colour_ms);
  fmt::print("{} triangles, {}x{} pictures from {} poses ({:.0f} % of pixels covered)\n", scene.triangles.size(),
             sim.camera().width_px, sim.camera().height_px, plain_ms.size(),
             100.0 * static_cast<double>(covered) /
                 (static_cast<double>(plain_ms.size()) * sim.camera().width_px * sim.camera().height_px));
  fmt::print("depth + face id: {:.2f} / {:.2f} ms (median / p95); with colour {:.2f} / {:.2f} ms\n", p.median, p.p95,
             c.median, c.p95);
  return 0;
}
