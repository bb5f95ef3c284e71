#pragma once
// Internal to the pipeline module: stage 2 over the run. A frame's view waits texture_delay frames
// (RunParams) before it is refined, with its scan, image and masks, so that later scans have meshed
// what it saw; a refined textured view is then kept until texture_revisit to colour what was meshed
// since. Both queues are bounded by those settings; the views left at the end are refined against
// the final mesh.

#include <cstddef>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/pipeline/run.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::pipeline {

// A view waiting for its refinement.
struct WaitingView {
  Frame frame;
  std::size_t camera = 0;  // into frame.cameras
  semantics::SemanticObservation observation;
  bool texture = false;
  bool semantics = false;
  Isometry3d T_W_L = Isometry3d::Identity();
  std::size_t i = 0;  // its place in the range
};

class RefinementStage {
 public:
  // The mapper, settings and report must outlive the stage; refinement times and counts go to
  // `report`.
  RefinementStage(mapping::Mapper& mapper, const RunParams& params, RunReport& report);

  void add(WaitingView view) { waiting_.push_back(std::move(view)); }
  // The view of the range's i-th frame, while it waits (nullptr once refined, or never added).
  WaitingView* waitingView(std::size_t i);

  // After stage 1 of the range's i-th frame: refines the views now due (one a frame, more after an
  // unreadable frame) and revisits the kept views now due. Returns the voxels they all looked at
  // (nullopt: none was due).
  std::optional<mapping::RefinementStats> runDue(std::size_t i);
  // runDue's work, handed over to run beside the next frame's insert (Mapper::handOver): the views
  // due are looked at now, the rest is done by the next frame's integrate() or complete(). Results
  // as runDue's; for runs without an observer (the voxels looked at are not returned) and without
  // semantics (fusion would write what the work reads).
  void handOverDue(std::size_t i);
  // Does what handOverDue handed over, if it is not done yet: before anything else reads the views
  // or the colours.
  void complete() { mapper_.completeHandedOver(); }
  // Before the range's i-th frame is mapped: the views already waiting that will be due after it
  // are looked at beside its constraint (Mapper::besideNextConstraint), for handOverDue(i).
  void lookBesideConstraint(std::size_t i);
  // After the final meshing: every view still waiting or kept.
  std::optional<mapping::RefinementStats> flush();

  // Where the views it holds were taken (the LiDAR's and the cameras' origins): tiles near them
  // stay in memory.
  [[nodiscard]] std::vector<Eigen::Vector3f> viewPositions() const;
  // After tiles left memory (Mapper::evictTiles): the kept views' vertex counts, renumbered.
  void renumberVertices(const std::vector<std::uint32_t>& new_id);

  // Checkpoints (stage_checkpoint.cpp): the waiting views whole (scan, image, masks); the kept
  // views' reference depths, their images read again from `dataset` on load.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in, const datasets::Dataset& dataset);

 private:
  struct KeptView {
    CameraView view;
    mapping::ViewMemory memory;
    std::size_t i = 0;
    std::size_t index = 0;  // the frame's
  };
  // `keep`: the view is kept for a revisit (not after the final meshing: nothing is added since).
  mapping::RefinementStats refine(WaitingView& view, bool keep);
  mapping::RefinementStats revisit(const KeptView& kept);
  // What refine() gives the mapper for `view`, filling `memory` when the view is kept.
  [[nodiscard]] mapping::RefinementInput inputOf(WaitingView& view, bool keep, mapping::ViewMemory& memory) const;
  // After a view's refinement (or revisit) that took `ms`: the view kept, the report and the log.
  void refined(WaitingView& view, mapping::ViewMemory& memory, const mapping::RefinementStats& r, double ms);
  void revisited(const KeptView& kept, const mapping::RefinementStats& r, double ms);
  // The views handOverDue took, their inputs and looks.
  struct HandedViews;

  mapping::Mapper& mapper_;
  const RunParams& params_;
  RunReport& report_;
  bool revisits_;
  std::deque<WaitingView> waiting_;  // oldest first
  std::deque<KeptView> kept_;        // oldest first
  // Looks taken beside a frame's constraint (lookBesideConstraint), by the view's place in the
  // range; handOverDue uses and clears them.
  std::vector<std::pair<std::size_t, mapping::ViewLook>> early_looks_;
};

}  // namespace artemis::pipeline
