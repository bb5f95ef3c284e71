#pragma once
// Simulators shared by the tests of one process: the default street, with and without noise.

#include "artemis/sim/simulator.hpp"

namespace artemis::test {

inline sim::SimParams testParams(int frames, double range_noise_m) {
  sim::SimParams p;
  p.frames = frames;
  p.lidar.range_noise_m = range_noise_m;
  return p;
}

inline const sim::Simulator& defaultSim() {
  static const sim::Simulator s(testParams(6, sim::LidarParams{}.range_noise_m));
  return s;
}

inline const sim::Simulator& noiseFreeSim() {
  static const sim::Simulator s(testParams(6, 0.0));
  return s;
}

}  // namespace artemis::test
