#pragma once
// The simulated street as a Dataset that makes each frame when it is read (scan and camera image),
// so that a benchmark can drive the whole pipeline down a street of any length without writing
// the recording to disk first. Poses are the simulator's exact ones.

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "artemis/datasets/dataset.hpp"
#include "artemis/sim/simulator.hpp"

namespace artemis::bench {

class SimDataset final : public datasets::Dataset {
 public:
  // `root`: reported as the recording's folder (nothing is read from it).
  static Result<std::unique_ptr<SimDataset>> open(const sim::SimParams& params, std::filesystem::path root) {
    std::unique_ptr<SimDataset> dataset(new SimDataset(params, std::move(root)));
    if (Status s = dataset->selectRange(); !s.isOk()) return s;
    return dataset;
  }

  [[nodiscard]] std::string format() const override { return "simulated street (in memory)"; }
  [[nodiscard]] std::filesystem::path root() const override { return root_; }
  [[nodiscard]] std::vector<CameraView> cameras() const override {
    CameraView view;
    view.name = "image_02";
    view.camera = sim_.camera();
    view.T_L_C = sim_.T_L_C();
    return {view};
  }
  [[nodiscard]] const sim::Simulator& simulator() const { return sim_; }

  // In lockstep, recording frame i is made only once framesMapped(i) was told: the pipeline's
  // reader, which reads the next frame while the current one is mapped, then waits instead of
  // simulating on the cores the mapping uses (a frame costs the simulator more than it costs the
  // mapping). A frame never reported (one that failed) holds the next back for at most kLockstepWait.
  void setLockstep(bool on) {
    const std::lock_guard lock(mutex_);
    lockstep_ = on;
  }
  void framesMapped(std::size_t done) {
    {
      const std::lock_guard lock(mutex_);
      mapped_ = done;
    }
    mapped_changed_.notify_all();
  }

 protected:
  [[nodiscard]] Result<Frame> readFrame(std::size_t recording_index) const override {
    const int i = static_cast<int>(recording_index);
    {
      std::unique_lock lock(mutex_);
      mapped_changed_.wait_for(lock, kLockstepWait, [&] { return !lockstep_ || mapped_ >= recording_index; });
    }
    Frame frame;
    frame.index = recording_index;
    frame.stamp_s = sim_.stamp_s(i);
    frame.scan_start_s = frame.stamp_s;
    frame.scan_end_s = frame.stamp_s;
    frame.T_W_L = sim_.T_W_L(i);
    const sim::LidarScan scan = sim_.scan(i);
    frame.points_L.reserve(scan.points_L.size());
    for (const Eigen::Vector4f& p : scan.points_L) {
      frame.points_L.points.push_back(p.head<3>());
      frame.points_L.intensity.push_back(p.w());
    }
    frame.stats.raw_points = scan.points_L.size();
    frame.cameras = cameras();
    frame.cameras.front().image = sim_.render(i).rgb;
    return frame;
  }

 private:
  SimDataset(const sim::SimParams& params, std::filesystem::path root)
      : Dataset(datasets::DatasetOptions{}), sim_(params), root_(std::move(root)) {
    for (int i = 0; i < sim_.frames(); ++i) {
      stamps_s_.push_back(sim_.stamp_s(i));
      poses_.push_back(sim_.T_W_L(i));
    }
    has_poses_ = true;
  }

  static constexpr std::chrono::seconds kLockstepWait{60};
  sim::Simulator sim_;
  std::filesystem::path root_;
  mutable std::mutex mutex_;
  mutable std::condition_variable mapped_changed_;
  bool lockstep_ = false;
  std::size_t mapped_ = 0;  // frames mapped so far (framesMapped)
};

}  // namespace artemis::bench
