#include "refinement_stage.hpp"

#include <algorithm>
#include <memory>
#include <span>
#include <vector>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"

namespace artemis::pipeline {

namespace {

// The voxels of every view refined or revisited in a frame (or at the end), for the observer.
void absorb(std::optional<mapping::RefinementStats>& into, mapping::RefinementStats r) {
  if (into) {
    into->voxels.insert(into->voxels.end(), r.voxels.begin(), r.voxels.end());
  } else {
    into = std::move(r);
  }
}

}  // namespace

RefinementStage::RefinementStage(mapping::Mapper& mapper, const RunParams& params, RunReport& report)
    : mapper_(mapper),
      params_(params),
      report_(report),
      revisits_(params.texture && params.texture_revisit > params.texture_delay) {}

std::vector<Eigen::Vector3f> RefinementStage::viewPositions() const {
  std::vector<Eigen::Vector3f> out;
  for (const WaitingView& w : waiting_) out.push_back(w.T_W_L.translation().cast<float>());
  for (const KeptView& k : kept_) out.push_back(k.memory.T_W_C.translation().cast<float>());
  return out;
}

void RefinementStage::renumberVertices(const std::vector<std::uint32_t>& new_id) {
  for (KeptView& k : kept_) {
    // Vertices below the old count that stayed are the vertices below the new one (ids keep
    // their order): the new count is one past the last of them.
    std::uint32_t v = std::min<std::uint32_t>(k.memory.vertices, static_cast<std::uint32_t>(new_id.size()));
    while (v > 0 && new_id[v - 1] == mapping::SemanticMesh::kGone) --v;
    k.memory.vertices = v == 0 ? 0 : new_id[v - 1] + 1;
  }
}

WaitingView* RefinementStage::waitingView(std::size_t i) {
  const auto view = std::find_if(waiting_.begin(), waiting_.end(), [i](const WaitingView& v) { return v.i == i; });
  return view == waiting_.end() ? nullptr : &*view;
}

std::optional<mapping::RefinementStats> RefinementStage::runDue(std::size_t i) {
  std::optional<mapping::RefinementStats> looked_at;
  const auto delay = static_cast<std::size_t>(params_.texture_delay);
  for (; !waiting_.empty() && waiting_.front().i + delay <= i; waiting_.pop_front()) {
    absorb(looked_at, refine(waiting_.front(), true));
  }
  const auto revisit_after = static_cast<std::size_t>(params_.texture_revisit);
  for (; !kept_.empty() && kept_.front().i + revisit_after <= i; kept_.pop_front()) {
    absorb(looked_at, revisit(kept_.front()));
  }
  return looked_at;
}

std::optional<mapping::RefinementStats> RefinementStage::flush() {
  std::optional<mapping::RefinementStats> looked_at;
  for (; !waiting_.empty(); waiting_.pop_front()) absorb(looked_at, refine(waiting_.front(), false));
  for (; !kept_.empty(); kept_.pop_front()) absorb(looked_at, revisit(kept_.front()));
  return looked_at;
}

mapping::RefinementInput RefinementStage::inputOf(WaitingView& d, bool keep, mapping::ViewMemory& memory) const {
  return {&d.frame.cameras[d.camera],
          d.texture,
          d.semantics ? &d.observation : nullptr,
          &d.frame.points_L,
          keep && revisits_ && d.texture ? &memory : nullptr,
          params_.semantics.vocabulary};
}

mapping::RefinementStats RefinementStage::refine(WaitingView& d, bool keep) {
  Stopwatch clock;
  mapping::ViewMemory memory;
  const mapping::RefinementStats r = mapper_.refine(inputOf(d, keep, memory), d.T_W_L);
  refined(d, memory, r, clock.elapsedMs());
  return r;
}

void RefinementStage::refined(WaitingView& d, mapping::ViewMemory& memory, const mapping::RefinementStats& r,
                              double ms) {
  if (!memory.empty()) kept_.push_back({std::move(d.frame.cameras[d.camera]), std::move(memory), d.i, d.frame.index});
  report_.times.add("refine", ms);
  report_.frames_textured += d.texture ? 1 : 0;
  report_.frames_semantic_refined += d.semantics ? 1 : 0;
  log::debug(
      "frame {}: refinement: {} voxels in view, {} faces rendered, {} vertices in view, {} coloured, {} "
      "labelled, gain {:.3f}; cull {:.1f} ms, depth {:.1f} ms, fuse {:.1f} ms",
      d.frame.index, r.voxels_in_view, r.faces_rendered, r.vertices_in_view, r.vertices_updated, r.vertices_labelled,
      r.gain, r.cull_ms, r.depth_ms, r.fuse_ms);
}

mapping::RefinementStats RefinementStage::revisit(const KeptView& k) {
  Stopwatch clock;
  const mapping::RefinementStats r = mapper_.revisit(k.view, k.memory);
  revisited(k, r, clock.elapsedMs());
  return r;
}

void RefinementStage::revisited(const KeptView& k, const mapping::RefinementStats& r, double ms) {
  report_.times.add("revisit", ms);
  log::debug("frame {}: revisit: {} grey vertices added since in view, {} coloured (in {} voxels); {:.1f} ms", k.index,
             r.vertices_in_view, r.vertices_updated, r.voxels_in_view, ms);
}

struct RefinementStage::HandedViews {
  std::vector<WaitingView> views;
  std::vector<mapping::ViewMemory> memories;
  std::vector<mapping::RefinementInput> inputs;  // into views and memories
  std::vector<mapping::ViewLook> looks;
  std::vector<KeptView> kept;
};

void RefinementStage::lookBesideConstraint(std::size_t i) {
  early_looks_.clear();
  const auto delay = static_cast<std::size_t>(params_.texture_delay);
  std::vector<WaitingView*> due;
  for (WaitingView& w : waiting_) {
    if (w.i + delay <= i) due.push_back(&w);
  }
  if (due.empty()) return;
  early_looks_.resize(due.size());
  // The look takes no memory; the views stay where they are in the queue until handOverDue.
  mapper_.besideNextConstraint([this, due] {
    for (std::size_t k = 0; k < due.size(); ++k) {
      mapping::ViewMemory unused;
      early_looks_[k] = {due[k]->i, mapper_.lookForRefinement(inputOf(*due[k], false, unused), due[k]->T_W_L)};
    }
  });
}

void RefinementStage::handOverDue(std::size_t i) {
  auto handed = std::make_shared<HandedViews>();
  const auto delay = static_cast<std::size_t>(params_.texture_delay);
  for (; !waiting_.empty() && waiting_.front().i + delay <= i; waiting_.pop_front()) {
    handed->views.push_back(std::move(waiting_.front()));
  }
  // The views refined now are kept after the revisits of this frame (as in runDue: a view is
  // never due for its revisit when it is refined).
  const auto revisit_after = static_cast<std::size_t>(params_.texture_revisit);
  for (; !kept_.empty() && kept_.front().i + revisit_after <= i; kept_.pop_front()) {
    handed->kept.push_back(std::move(kept_.front()));
  }
  if (handed->views.empty() && handed->kept.empty()) return;
  handed->memories.resize(handed->views.size());
  for (std::size_t k = 0; k < handed->views.size(); ++k) {
    handed->inputs.push_back(inputOf(handed->views[k], true, handed->memories[k]));
    const auto early = std::find_if(early_looks_.begin(), early_looks_.end(),
                                    [&](const auto& look) { return look.first == handed->views[k].i; });
    handed->looks.push_back(early != early_looks_.end()
                                ? std::move(early->second)
                                : mapper_.lookForRefinement(handed->inputs[k], handed->views[k].T_W_L));
  }
  early_looks_.clear();
  // It runs while the next frame is inserted, which touches none of the stage's views or the report.
  mapper_.handOver([this, handed](mapping::Mapper& mapper, std::span<const Eigen::Vector3f> positions) {
    for (std::size_t k = 0; k < handed->views.size(); ++k) {
      Stopwatch clock;
      WaitingView& d = handed->views[k];
      const mapping::ViewLook& look = handed->looks[k];
      const mapping::RefinementStats r = mapper.refineLooked(look, positions, handed->inputs[k], d.T_W_L);
      refined(d, handed->memories[k], r, look.cull_ms + look.copy_ms + clock.elapsedMs());
    }
    for (const KeptView& k : handed->kept) {
      Stopwatch clock;
      revisited(k, mapper.revisitUpTo(k.view, k.memory, positions), clock.elapsedMs());
    }
  });
}

}  // namespace artemis::pipeline
