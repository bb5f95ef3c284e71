#include "frame_reader.hpp"

namespace artemis::pipeline {

FrameReader::FrameReader(const datasets::Dataset& dataset, SegmentationStage* segmentation, std::size_t first)
    : dataset_(dataset), segmentation_(segmentation), next_(first) {
  if (next_ < dataset_.size()) pending_ = std::async(std::launch::async, &FrameReader::read, this, next_);
}

ReadFrame FrameReader::next() {
  ReadFrame got = pending_.get();
  if (++next_ < dataset_.size()) pending_ = std::async(std::launch::async, &FrameReader::read, this, next_);
  return got;
}

ReadFrame FrameReader::read(std::size_t i) const {
  ReadFrame r{dataset_.frame(i), {}};
  if (r.frame && segmentation_ != nullptr) r.segmented = segmentation_->segment(i, *r.frame);
  return r;
}

}  // namespace artemis::pipeline
