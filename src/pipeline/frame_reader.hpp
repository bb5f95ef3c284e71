#pragma once
// Internal to the pipeline module: the reading stage. While the mapping thread maps frame i, frame
// i + 1 is read (scan and image decoded) on a thread of its own and, offline, segmented there too
// (SegmentationStage): a queue one frame deep between reading and mapping.

#include <cstddef>
#include <future>

#include "artemis/core/frame.hpp"
#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/pipeline/segmentation_stage.hpp"

namespace artemis::pipeline {

struct ReadFrame {
  Result<Frame> frame;
  SegmentOutcome segmented;  // offline segmentation's outcome (due == false without it)
};

class FrameReader {
 public:
  // `segmentation`: offline segmentation riding with the reader, or nullptr. Both must outlive
  // the reader. Reading of the range's frame `first` (a resumed run's) starts here.
  FrameReader(const datasets::Dataset& dataset, SegmentationStage* segmentation, std::size_t first = 0);
  // Its reading thread holds `this`: neither copied nor moved.
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;

  // The range's next frame (waiting for it where it is not read yet); the one after starts reading.
  // Call at most dataset.size() - first times.
  ReadFrame next();

 private:
  ReadFrame read(std::size_t i) const;

  const datasets::Dataset& dataset_;
  SegmentationStage* segmentation_;
  std::size_t next_ = 0;
  std::future<ReadFrame> pending_;
};

}  // namespace artemis::pipeline
