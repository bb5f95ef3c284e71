#include "semantic_step.hpp"

#include <algorithm>

#include "artemis/core/log.hpp"

namespace artemis::pipeline {

SemanticStep::SemanticStep(const RunParams& params, mapping::Mapper& mapper, RunReport& report)
    : params_(params), sem_(params.semantics), mapper_(mapper), report_(report) {
  if (sem_.segmenter == nullptr) return;
  if (sem_.realtime) {
    live_ = std::make_unique<SegmentationWorker>(*sem_.segmenter);
  } else {
    offline_.emplace(*sem_.segmenter, *sem_.brush, sem_.camera, sem_.segment_every);
  }
}

FrameSemantics SemanticStep::frame(std::size_t i, const Frame& frame, const CameraView* view, SegmentOutcome& segmented,
                                   double read_ms) {
  FrameSemantics out;
  if (live_) {
    offer(i, frame, view, out);
  } else if (offline_) {
    take(segmented, frame.index, read_ms, out);
  }
  return out;
}

void SemanticStep::offer(std::size_t i, const Frame& frame, const CameraView* view, FrameSemantics& out) {
  const std::vector<semantics::ClassId> prompts = sem_.brush->beginFrame(i);
  for (const semantics::ClassId c : prompts) mapper_.addSemanticClass(c);
  if (i % static_cast<std::size_t>(sem_.segment_every) != 0) {
    ++report_.frames_not_due;
  } else if (view == nullptr || !view->hasImage()) {
    unobserved(frame.index, view == nullptr ? "the recording has no camera" : "no image " + view->image_path);
  } else {
    if (!view->name.empty()) report_.segmented_camera = view->name;
    out.offered = live_->offer({i, frame.index, *view, prompts});
    report_.frames_busy += out.offered ? 0 : 1;
  }
}

// Segmentation ran on the reader's thread; the mapping thread waited for it only where it took
// longer than mapping the frame before ("segment_wait", left out of "total").
void SemanticStep::take(SegmentOutcome& seg, std::size_t frame_index, double read_ms, FrameSemantics& out) {
  for (const semantics::ClassId c : seg.prompts) mapper_.addSemanticClass(c);
  if (!seg.due) {
    ++report_.frames_not_due;
    return;
  }
  if (!seg.camera.empty()) report_.segmented_camera = seg.camera;
  if (!seg.observation.observed) {
    unobserved(frame_index, seg.failure);
  } else {
    out.observation = std::move(seg.observation);
    ++report_.frames_observed;
  }
  report_.times.add("segment", seg.ms);
  out.wait_ms = std::min(read_ms, seg.ms);
  report_.times.add("segment_wait", out.wait_ms);
}

void SemanticStep::acceptArrived(RefinementStage& stage2) {
  if (live_) accept(live_->poll(), stage2);
}

void SemanticStep::drain(RefinementStage& stage2) {
  if (live_) accept(live_->drain(), stage2);
}

// Masks that arrived from the worker: fused into the cells of their frame's points now, and kept
// for the frame's stage 2 where its view still waits; after that they come too late.
void SemanticStep::accept(std::vector<SegmentationWorker::Done> arrived, RefinementStage& stage2) {
  for (SegmentationWorker::Done& done : arrived) {
    report_.times.add("segment", done.outcome.ms);
    if (!done.outcome.observation.observed) {
      unobserved(done.frame_index, done.outcome.failure);
      continue;
    }
    WaitingView* view = stage2.waitingView(done.i);
    if (view == nullptr) {
      ++report_.frames_late;
      continue;
    }
    view->observation = std::move(done.outcome.observation);
    const mapping::SemanticInput input{&view->frame.cameras[view->camera], &view->observation, sem_.vocabulary};
    report_.times.add("fuse", mapper_.fuseLate(view->frame.points_L, view->T_W_L, input).ms);
    view->semantics = params_.mapper.refinement.semantic_refinement;
    ++report_.frames_observed;
  }
}

void SemanticStep::unobserved(std::size_t frame_index, const std::string& why) {
  ++report_.frames_unobserved;
  if (++unobserved_logged_ <= 10) {
    log::warn("frame {}: no semantic observation: {}{}", frame_index, why,
              unobserved_logged_ == 10 ? " (further frames like this are counted, not logged)" : "");
  }
}

}  // namespace artemis::pipeline
