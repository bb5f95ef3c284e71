#pragma once
// The Living Map's mesh: vertices (the points the voxel map kept) with their normal, voxel of
// origin and viewing direction, and faces grouped by the voxel that owns them, so that re-meshing
// a voxel replaces exactly its faces. A change log says which voxels changed in the current frame
// (for the viewer and incremental exports).
//
// Semantics (eq. 1, 7): evidence is kept at two scales, both as accumulated observation weight per
// "slot" (slot 0: none of the prompted classes; slot s >= 1: the s-th class prompted in this run)
// and their sum W_sem:
//   - per voxel (the meshing voxel, 0.4 m): the paper's voxel distribution, evidence / W_sem;
//   - per vertex: the evidence of the vertex's own cell (the sub-cell it holds, 0.1 m).
// A vertex's distribution is its cell's evidence plus its voxel's distribution weighted by
// voxel_prior: the voxel's as it inherits it (eq. 7) wherever its own cell was never seen by the
// camera, sharpened by the cell's evidence wherever it was. Its confidence is eq. 7 with its
// voxel's W_sem. Slots, rather than the whole vocabulary, keep this at (1 + prompted classes)
// floats per vertex and per voxel.
//
// Stage 2 (eq. 12-13) adds per vertex the unnormalised log-probabilities lambda of its slots,
// summed over the views that saw it reliably. Once a vertex has some, its distribution is the
// softmax of lambda + kappa log(stage 1's distribution, floored at kStageOneFloor): stage 1 is the
// prior that the views' likelihoods sharpen, worth kappa views (setStageOneWeight).

#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/prefault.hpp"
#include "artemis/mapping/voxel_key.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::mapping {

using Face = std::array<std::uint32_t, 3>;

class SemanticMesh {
 public:
  // Vertices, structure of arrays; index = vertex id.
  [[nodiscard]] std::size_t vertexCount() const { return positions_.size(); }
  // Makes room for `count` more vertices now, so that adding them moves no per-vertex array (what
  // runs beside the adding keeps reading the arrays where they are).
  void reserveVertices(std::size_t count) {
    while (positions_.capacity() - positions_.size() < count) growVertexRoom();
  }
  [[nodiscard]] const std::vector<Eigen::Vector3f>& positions() const { return positions_; }
  [[nodiscard]] const std::vector<Eigen::Vector3f>& normals() const { return normals_; }
  [[nodiscard]] const std::vector<VoxelKey>& voxels() const { return voxels_; }
  // The dense index (VoxelMap's) of each vertex's voxel, as given to addVertex.
  [[nodiscard]] const std::vector<std::uint32_t>& voxelIndices() const { return voxel_index_; }
  // Unit direction from the vertex towards the sensor that first saw it.
  [[nodiscard]] const std::vector<Eigen::Vector3f>& viewDirections() const { return views_; }
  // Where the LiDAR measured the vertex; positions() may differ once the semantic constraint
  // (stage 1d) has moved it.
  [[nodiscard]] const std::vector<Eigen::Vector3f>& measuredPositions() const { return measured_; }
  void setPosition(std::uint32_t vertex, const Eigen::Vector3f& p_W) { positions_[vertex] = p_W; }

  // A vertex's number for the whole run (the count of vertices added before it): ids change when
  // tiles of the map leave memory (compactVertices), uids do not, and keep the ids' order. Tile
  // files name the vertices of other tiles by it.
  [[nodiscard]] std::uint64_t uid(std::uint32_t v) const { return uids_[v]; }
  // The voxel index of a vertex whose voxel left memory while the vertex stayed (a face of a voxel
  // still in memory uses it).
  static constexpr std::uint32_t kNoVoxel = 0xFFFFFFFFu;

  // `voxel_index` numbers the voxel densely (VoxelMap's index): it keys the voxel's semantics.
  std::uint32_t addVertex(const Eigen::Vector3f& p_W, const VoxelKey& voxel, const Eigen::Vector3f& to_sensor,
                          std::uint32_t voxel_index = 0);
  void setNormal(std::uint32_t vertex, const Eigen::Vector3f& normal) { normals_[vertex] = normal; }

  // Replaces the faces owned by `voxel` and logs the change.
  void setVoxelFaces(const VoxelKey& voxel, std::vector<Face> faces);
  [[nodiscard]] const std::vector<Face>* voxelFaces(const VoxelKey& voxel) const;
  // Voxels that own faces (any order).
  [[nodiscard]] std::vector<VoxelKey> faceOwners() const;
  // Forgets the faces of `voxel` without logging a change: they left memory for a tile file, and
  // an observer keeps showing what it was shown.
  void dropVoxelFaces(const VoxelKey& voxel);
  [[nodiscard]] std::size_t faceCount() const { return face_count_; }
  // Every face, voxel by voxel in key order (deterministic).
  [[nodiscard]] std::vector<Face> faces() const;

  // Semantic slots: slot -> class (slot 0 is kNoClass). Adding a class adds a slot with no evidence
  // to every vertex; a class already present keeps its slot. Returns the class's slot.
  std::size_t addSemanticClass(semantics::ClassId cls);
  [[nodiscard]] const std::vector<semantics::ClassId>& semanticSlots() const { return slots_; }
  [[nodiscard]] std::size_t slotCount() const { return slots_.size(); }
  // Slot of `cls`, or -1 when it has none.
  [[nodiscard]] int slotOf(semantics::ClassId cls) const;
  // Evidence of vertex v's cell per slot (slotCount() values), or nullptr for a cell never
  // observed; valid until vertices or classes are added. Its W_sem, 0 when never observed.
  [[nodiscard]] const float* classEvidence(std::uint32_t v) const {
    return v < semantic_weight_.size() ? &evidence_[static_cast<std::size_t>(v) * slots_.size()] : nullptr;
  }
  [[nodiscard]] float semanticWeight(std::uint32_t v) const {
    return v < semantic_weight_.size() ? semantic_weight_[v] : 0.0f;
  }
  // W_sem of vertex v's voxel.
  [[nodiscard]] float voxelSemanticWeight(std::uint32_t v) const;
  // Adds an observation of weight `w` for `slot` to vertex v's cell and to its voxel.
  void observe(std::uint32_t v, std::size_t slot, float w);
  // Adds an observation of weight `w` spread over the slots as `p` (slotCount() values summing to
  // 1): a dense segmenter's distribution at the point's pixel.
  void observeDistribution(std::uint32_t v, const float* p, float w);
  // Weight of the voxel's distribution in a vertex's (see above); > 0.
  void setVoxelPrior(float weight) { voxel_prior_ = weight; }
  // Stage 2: makes room for every vertex's lambda (call before addLogLikelihood, which may then run
  // concurrently for distinct vertices).
  void reserveRefinement();
  // lambda_v,s += w * (s == hit_slot ? log_hit : log_miss) (eq. 12-13), and w to v's refined weight.
  void addLogLikelihood(std::uint32_t v, std::size_t hit_slot, float log_hit, float log_miss, float w);
  // lambda_v,s += w * log_p[s] for every slot (a dense observation's log P_mask per slot).
  void addLogLikelihoods(std::uint32_t v, const float* log_p, float w);
  // Sum of the W that refined vertex v's classes (0: never).
  [[nodiscard]] float refinedWeight(std::uint32_t v) const {
    return v < refined_weight_.size() ? refined_weight_[v] : 0.0f;
  }
  static constexpr float kStageOneFloor = 1e-3f;
  // kappa above; > 0.
  void setStageOneWeight(float kappa) { stage_one_weight_ = kappa; }
  // Vertex v's distribution over the slots (slotCount() values, summing to 1), or false when
  // neither its cell nor its voxel was ever observed and no view refined it.
  bool distribution(std::uint32_t v, float* out) const;
  // The slot with the highest probability (kNoClass when never observed; ties go to the lower slot).
  [[nodiscard]] semantics::ClassId vertexClass(std::uint32_t v) const;
  // eq. 7: xi = 1 - exp(-lambda W_sem(voxel of v)).
  [[nodiscard]] float confidence(std::uint32_t v, double lambda) const;

  // Texture (stage 2): per vertex a Gaussian colour in linear RGB, mean and per-channel variance.
  [[nodiscard]] bool hasColour(std::uint32_t v) const { return v < colour_var_.size() && colour_var_[v].x() > 0.0f; }
  [[nodiscard]] Eigen::Vector3f colourMean(std::uint32_t v) const {
    return hasColour(v) ? colour_mean_[v] : Eigen::Vector3f::Zero();
  }
  [[nodiscard]] Eigen::Vector3f colourVariance(std::uint32_t v) const {
    return hasColour(v) ? colour_var_[v] : Eigen::Vector3f::Zero();
  }
  // Makes room for every vertex's colour (call before fuseColour, which may then run concurrently
  // for distinct vertices); or for the first `count` vertices' (it never shrinks).
  void reserveColours() { reserveColours(positions_.size()); }
  void reserveColours(std::size_t count);
  // The room reserved past the end of every array that grows with the vertices, for `count` more
  // (populatePages).
  [[nodiscard]] std::vector<ByteRange> roomAhead(std::size_t count) const;
  // Fuses an observation `c` with per-channel variance `variance` (> 0) into vertex v's colour: the
  // first sets it, later ones update mean and variance as a Kalman filter does.
  void fuseColour(std::uint32_t v, const Eigen::Vector3f& c, float variance);

  // The frame's change log: voxels whose faces were replaced, and face counts added and removed.
  struct Changes {
    std::vector<VoxelKey> voxels;
    std::size_t faces_added = 0;
    std::size_t faces_removed = 0;
  };
  void beginFrame() { changes_ = {}; }
  [[nodiscard]] const Changes& changes() const { return changes_; }

  // Vertices used by at least one face, and the faces renumbered onto them: what exporters write.
  struct Compact {
    std::vector<std::uint32_t> vertex_ids;  // into this mesh's arrays
    std::vector<Face> faces;                // indices into vertex_ids
  };
  [[nodiscard]] Compact compact() const;

  // Tiles leaving memory: keeps vertex v (new_id[v] != kGone) as vertex new_id[v], the kept ones
  // numbered densely in their old order, and renumbers the faces, every one of whose vertices must
  // be kept. The voxels are renumbered too, by voxel_new_id (VoxelMap::removeVoxels): a kept
  // vertex whose voxel is gone gets kNoVoxel, and the evidence of the gone voxels goes with them.
  static constexpr std::uint32_t kGone = 0xFFFFFFFFu;
  void compactVertices(const std::vector<std::uint32_t>& new_id, const std::vector<std::uint32_t>& voxel_new_id);

  // Tiles coming back (tile_state.cpp). saveVertices writes every per-vertex value of vertices
  // `ids`, in that order; loadVertices reads them back: file vertex i overwrites the vertex
  // `existing(uid)` names (one that stayed in memory for a face that used it), or is added when
  // that is kGone. Returns the ids in file order; their voxel index is kNoVoxel until set.
  // Classes the file has and this mesh lacks are added. Both throw ArchiveError (load: on damage).
  void saveVertices(ArchiveWriter& out, const std::vector<std::uint32_t>& ids) const;
  std::vector<std::uint32_t> loadVertices(ArchiveReader& in,
                                          const std::function<std::uint32_t(std::uint64_t)>& existing);
  void setVoxelIndex(std::uint32_t v, std::uint32_t voxel_index) { voxel_index_[v] = voxel_index; }
  // The semantic evidence of voxels `voxels` (VoxelMap indices), and back into other indices.
  void saveVoxelSemantics(ArchiveWriter& out, const std::vector<std::uint32_t>& voxels) const;
  void loadVoxelSemantics(ArchiveReader& in, const std::vector<std::uint32_t>& voxels);
  // A vertex of a finished tile that a face in memory uses (voxel index kNoVoxel), as its tile file
  // holds it: position, normal and, when `colour` is given, its colour (linear RGB).
  std::uint32_t addGhost(const Eigen::Vector3f& p_W, const Eigen::Vector3f& normal, const VoxelKey& voxel,
                         std::uint64_t uid, const Eigen::Vector3f* colour);
  // Adds `more` to this frame's change log.
  void addChanges(const Changes& more);

  // Checkpoints (mapping/checkpoint.cpp): every vertex, face and weight; load() into an empty mesh
  // with the same voxel prior and stage-one weight (set from the same params). After load() the
  // change log lists every voxel with faces.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  static constexpr std::size_t kVertexRoom = std::size_t{1} << 22;
  // Tiles coming back: the slots a tile state was written with, each as this mesh's slot (classes
  // it lacks are added).
  std::vector<std::size_t> readSlots(ArchiveReader& in);
  // Reserves room for at least kVertexRoom vertices (twice the present room once past it) in every
  // per-vertex array.
  void growVertexRoom();

  std::vector<Eigen::Vector3f> positions_;
  std::vector<Eigen::Vector3f> measured_;
  std::vector<Eigen::Vector3f> normals_;
  std::vector<VoxelKey> voxels_;
  std::vector<Eigen::Vector3f> views_;
  std::vector<std::uint64_t> uids_;
  std::uint64_t next_uid_ = 0;
  std::vector<semantics::ClassId> slots_{semantics::kNoClass};
  // Stage 1's distribution of vertex v, whose cell and voxel weights are given (not both 0).
  void stageOne(std::uint32_t v, float w_cell, float w_voxel, float* out) const;

  std::vector<float> evidence_;             // vertex-major, slotCount() per vertex observed so far
  std::vector<float> semantic_weight_;      // W_sem per vertex; grows to the highest vertex observed
  std::vector<std::uint32_t> voxel_index_;  // per vertex
  std::vector<float> voxel_evidence_;       // voxel-major, slotCount() per voxel
  std::vector<float> voxel_weight_;         // W_sem per voxel
  float voxel_prior_ = 10.0f;
  std::vector<float> log_likelihood_;  // lambda, vertex-major, slotCount() per vertex
  std::vector<float> refined_weight_;  // per vertex
  float stage_one_weight_ = 5.0f;
  std::vector<Eigen::Vector3f> colour_mean_;
  std::vector<Eigen::Vector3f> colour_var_;  // 0: never coloured
  std::unordered_map<VoxelKey, std::vector<Face>, VoxelKeyHash> faces_;
  std::size_t face_count_ = 0;
  Changes changes_;
};

}  // namespace artemis::mapping
