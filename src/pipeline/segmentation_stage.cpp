#include "artemis/pipeline/segmentation_stage.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

#include "artemis/core/timer.hpp"

namespace artemis::pipeline {

const CameraView* segmentedView(const Frame& frame, const std::string& camera) {
  for (const CameraView& c : frame.cameras) {
    if (c.name == camera) return &c;
  }
  return frame.cameras.empty() ? nullptr : &frame.cameras.front();
}

SegmentationStage::SegmentationStage(semantics::Segmenter& segmenter, semantics::ActiveBrush& brush, std::string camera,
                                     int segment_every)
    : segmenter_(segmenter),
      brush_(brush),
      camera_(std::move(camera)),
      every_(static_cast<std::size_t>(segment_every)) {
  if (segment_every < 1) throw std::invalid_argument("segmentation: segment_every must be >= 1");
}

SegmentOutcome segmentView(semantics::Segmenter& segmenter, std::size_t frame_index, const CameraView* view,
                           std::vector<semantics::ClassId> prompts) {
  SegmentOutcome out;
  Stopwatch clock;
  out.due = true;
  out.prompts = std::move(prompts);
  if (view != nullptr) out.camera = view->name;
  if (view == nullptr) {
    out.failure = "the recording has no camera";
  } else if (!view->hasImage()) {
    out.failure = fmt::format("no image {}", view->image_path);
  } else {
    auto segmented = segmenter.segment({frame_index, view}, out.prompts);
    if (!segmented) {
      out.failure = segmented.status().message();
    } else if (!segmented->observed) {
      out.failure = segmented->note;
    } else if (Status valid = segmented->validate(out.prompts); !valid.isOk()) {
      out.failure = fmt::format("{} segmenter: {}", segmenter.name(), valid.message());
    } else {
      out.observation = std::move(*segmented);
    }
  }
  out.ms = clock.elapsedMs();
  return out;
}

SegmentOutcome SegmentationStage::segment(std::size_t i, const Frame& frame) {
  // The brush applies new queries at every frame, segmented or not.
  std::vector<semantics::ClassId> prompts = brush_.beginFrame(i);
  if (i % every_ != 0) {
    SegmentOutcome out;
    out.prompts = std::move(prompts);
    return out;
  }
  return segmentView(segmenter_, frame.index, segmentedView(frame, camera_), std::move(prompts));
}

SegmentationWorker::SegmentationWorker(semantics::Segmenter& segmenter)
    : segmenter_(segmenter), thread_([this] { loop(); }) {}

SegmentationWorker::~SegmentationWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

bool SegmentationWorker::offer(Job job) {
  {
    std::lock_guard lock(mutex_);
    if (job_) return false;
    job_ = std::move(job);
  }
  wake_.notify_all();
  return true;
}

std::vector<SegmentationWorker::Done> SegmentationWorker::poll() {
  std::lock_guard lock(mutex_);
  return std::exchange(done_, {});
}

std::vector<SegmentationWorker::Done> SegmentationWorker::drain() {
  std::unique_lock lock(mutex_);
  wake_.wait(lock, [this] { return !job_; });
  return std::exchange(done_, {});
}

void SegmentationWorker::loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || job_; });
    if (!job_) return;  // stopping with nothing in flight
    const Job& job = *job_;
    lock.unlock();
    Done done{job.i, job.frame_index, segmentView(segmenter_, job.frame_index, &job.view, job.prompts)};
    lock.lock();
    done_.push_back(std::move(done));
    job_.reset();
    wake_.notify_all();
  }
}

}  // namespace artemis::pipeline
