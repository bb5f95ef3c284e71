#pragma once
// Segmentation as a stage of its own, in one of two ways:
//   - offline (SegmentationStage): the pipeline's reader thread segments frame k + 1 (scan and image
//     just decoded) while the mapping thread maps frame k, so a network's forward pass overlaps
//     mapping; every frame due is segmented and the outcome travels with the frame;
//   - real time (SegmentationWorker): the segmenter runs on a thread of its own and takes the
//     newest frame whenever it is free; the mapper never waits, and fuses masks when they arrive.

#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/semantics/active_brush.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::pipeline {

struct SegmentOutcome {
  bool due = false;  // the frame was to be segmented (semantics on, and its turn by segment_every)
  std::vector<semantics::ClassId> prompts;
  semantics::SemanticObservation observation;  // observed == false: see failure
  std::string failure;                         // why there is no observation
  std::string camera;                          // the segmented camera's name
  double ms = 0.0;                             // the segmenter's time
};

// The camera a frame's semantics and texture use: the one named, else the frame's first (nullptr
// when it has none).
const CameraView* segmentedView(const Frame& frame, const std::string& camera);

class SegmentationStage {
 public:
  // The objects must outlive the stage; segment_every >= 1.
  SegmentationStage(semantics::Segmenter& segmenter, semantics::ActiveBrush& brush, std::string camera,
                    int segment_every);
  // Segments the `i`-th frame of the range with the brush's prompts for it. Call in frame order,
  // one call at a time (from any thread).
  SegmentOutcome segment(std::size_t i, const Frame& frame);

 private:
  semantics::Segmenter& segmenter_;
  semantics::ActiveBrush& brush_;
  std::string camera_;
  std::size_t every_;
};

// Segments `view` (nullptr: the frame has no camera) with `prompts` into an outcome; `due` is set.
SegmentOutcome segmentView(semantics::Segmenter& segmenter, std::size_t frame_index, const CameraView* view,
                           std::vector<semantics::ClassId> prompts);

class SegmentationWorker {
 public:
  struct Job {
    std::size_t i = 0;  // the frame's place in the range
    std::size_t frame_index = 0;
    CameraView view;
    std::vector<semantics::ClassId> prompts;
  };
  struct Done {
    std::size_t i = 0;
    std::size_t frame_index = 0;
    SegmentOutcome outcome;
  };

  explicit SegmentationWorker(semantics::Segmenter& segmenter);
  ~SegmentationWorker();  // finishes the job in flight
  SegmentationWorker(const SegmentationWorker&) = delete;
  SegmentationWorker& operator=(const SegmentationWorker&) = delete;

  // Hands `job` to the segmenter when it is free; false (the job is not taken) when it is busy.
  bool offer(Job job);
  // The jobs finished since the last call, oldest first.
  std::vector<Done> poll();
  // Waits for the job in flight, then poll().
  std::vector<Done> drain();

 private:
  void loop();

  semantics::Segmenter& segmenter_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<Job> job_;  // taken or waiting to be taken
  bool stop_ = false;
  std::vector<Done> done_;
  std::thread thread_;
};

}  // namespace artemis::pipeline
