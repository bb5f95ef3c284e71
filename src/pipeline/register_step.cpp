#include "register_step.hpp"

#include <utility>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/registration/deskew.hpp"

namespace artemis::pipeline {

Isometry3d RegisterStep::run(Frame& frame, const Isometry3d& prior, const std::optional<Isometry3d>& last_T,
                             int frames_since, double last_stamp_s, RunReport& report) {
  if (odometry_ == nullptr && !deskew_) return prior;
  Stopwatch register_clock;
  // Motion and period both span the frames since the last mapped one.
  if (deskew_ && last_T) deskew(frame, last_T->inverse() * prior, frame.stamp_s - last_stamp_s);
  Isometry3d T_W_L = prior;
  if (odometry_ != nullptr) {
    auto reg = odometry_->registerScan(frame.points_L.points, prior, last_T ? frames_since : 1);
    T_W_L = reg.T_W_L;
    if (reg.fallback) {
      ++report.registration_fallbacks;
      log::warn("frame {}: registration kept the prior pose ({})", frame.index, reg.reason);
    } else if (reg.icp.degenerate_directions > 0) {
      ++report.degenerate_frames;
      log::warn("frame {}: {}", frame.index, reg.reason);
    }
    log::debug(
        "frame {}: registered in {:.1f} ms, {} iterations, {} correspondences, rms {:.3f} m, "
        "correction {:.3f} m {:.3f} deg",
        frame.index, reg.ms, reg.icp.iterations, reg.icp.correspondences, reg.icp.rms_m, reg.correction_m,
        reg.correction_deg);
    report.registrations.push_back(std::move(reg));
    report.registered_frames.push_back(frame.index);
  }
  report.times.add("register", register_clock.elapsedMs());
  return T_W_L;
}

void RegisterStep::deskew(Frame& frame, const Isometry3d& motion, double period_s) {
  std::vector<float>& times = frame.points_L.time_s;
  if (!times.empty()) {  // the recording's own per-point times
    if (registration::deskewScan(frame.points_L.points, times, motion, period_s)) {
      times.clear();  // every point now stands where the sensor saw it at the stamp
    } else {
      ++not_deskewed_;
      log::warn("frame {}: not deskewed: {:.3f} s since the last frame against a sweep of {:.3f} s", frame.index,
                period_s, frame.scan_end_s - frame.scan_start_s);
    }
    return;
  }
  const registration::SweepTiming timing{frame.stamp_s, frame.scan_start_s, frame.scan_end_s};
  if (timing.known()) {
    if (!registration::deskewScan(frame.points_L.points, motion, period_s, timing)) {
      ++not_deskewed_;
      log::warn("frame {}: not deskewed: {:.3f} s since the last frame against a {:.3f} s sweep", frame.index, period_s,
                timing.end_s - timing.start_s);
    }
  } else if (!warned_no_sweep_) {
    log::warn("{}: no sweep start/end stamps or per-point times, so scans are not deskewed", recording_.string());
    warned_no_sweep_ = true;
  }
}

}  // namespace artemis::pipeline
