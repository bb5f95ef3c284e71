#pragma once
// Internal to the pipeline module: what a run does with semantics for each frame. Offline, the
// reader segmented the frame (SegmentationStage) and its outcome is taken here; in real time the
// frame is offered to the segmentation worker, whose masks are fused when they arrive: into stage
// 1 late, by the cells of the frame's points, and into stage 2 while the frame's view still waits
// (RefinementStage). Counts and times go to the run's report.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/pipeline/segmentation_stage.hpp"
#include "refinement_stage.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::pipeline {

// A frame's semantics for stage 1.
struct FrameSemantics {
  semantics::SemanticObservation observation;  // observed == false: nothing to fuse now
  bool offered = false;                        // real time: the worker took the frame
  double wait_ms = 0.0;                        // offline: how long mapping waited for the segmenter
};

class SemanticStep {
 public:
  // Semantics on when params.semantics.segmenter is set (with a brush and a vocabulary). The
  // objects must outlive the step.
  SemanticStep(const RunParams& params, mapping::Mapper& mapper, RunReport& report);
  // The reader holds a pointer to its offline stage: neither copied nor moved.
  SemanticStep(const SemanticStep&) = delete;
  SemanticStep& operator=(const SemanticStep&) = delete;

  // Offline segmentation, for the reader to run; nullptr in real time or without semantics.
  SegmentationStage* offline() { return offline_ ? &*offline_ : nullptr; }

  // The range's i-th frame, with `view` its segmented camera, `segmented` the reader's outcome and
  // `read_ms` the time mapping waited for the reader.
  FrameSemantics frame(std::size_t i, const Frame& frame, const CameraView* view, SegmentOutcome& segmented,
                       double read_ms);
  // Real time: fuses the masks that arrived since (after the frame's view joined stage 2).
  void acceptArrived(RefinementStage& stage2);
  // Real time: waits for the job in flight and fuses what arrived (after the final meshing).
  void drain(RefinementStage& stage2);

  // Checkpoints (stage_checkpoint.cpp): its counts. In real time, drain() first.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  void offer(std::size_t i, const Frame& frame, const CameraView* view, FrameSemantics& out);
  void take(SegmentOutcome& segmented, std::size_t frame_index, double read_ms, FrameSemantics& out);
  void accept(std::vector<SegmentationWorker::Done> arrived, RefinementStage& stage2);
  void unobserved(std::size_t frame_index, const std::string& why);

  const RunParams& params_;
  const SemanticRunParams& sem_;
  mapping::Mapper& mapper_;
  RunReport& report_;
  std::optional<SegmentationStage> offline_;
  std::unique_ptr<SegmentationWorker> live_;
  std::size_t unobserved_logged_ = 0;
};

}  // namespace artemis::pipeline
