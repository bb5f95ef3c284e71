#pragma once
// `artemis run`: reads a recording frame by frame, builds the Living Map, and writes
//   <out>/mesh.ply        binary PLY: float x y z, float nx ny nz (towards the sensor), with texture
//                         uchar red green blue (sRGB; grey where no view coloured a vertex), faces; with
//                         semantics also uchar class_id (vocabulary id, 0: none of the prompted
//                         classes or never observed), float confidence (xi of eq. 7) and, when
//                         asked, float prob_<class> per prompted class and prob_none
//   <out>/mesh_classes.ply   with semantics: the same mesh coloured by class (uchar red green blue)
//   <out>/semantics.json  with semantics: {"vocabulary": {...}, "prompted": [ids], "queries": [...],
//                         "segmenter": name, "frames_observed", "frames_unobserved", "fusion": {...}}
//   <out>/trajectory.txt  T_W_L of every frame of the range (registered where pose refinement is
//                         on), 12 numbers a line (row-major 3x4)
//   <out>/registration.json  with pose refinement: per frame, what ICP did (see registrationJson)
//   <out>/config.json     the effective settings (given by the caller)
//   <out>/timing.json     {"frames": N, "stages": {"<stage>": {"median_ms", "p95_ms", "max_ms"}, ...,
//                          "total": {...}}, "cpu": {...} (all threads' CPU time while each frame was
//                          mapped), "finish_ms", "peak_rss_mb", "page_faults", "frames_failed",
//                          "points_in_vehicle_path", "points_carved", "holes_filled", "checkpoints":
//                          {"written", "last_mb", "max_ms", "resumed_at_frame"}}
// Every file is written atomically.

#include <atomic>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/pipeline/timing.hpp"
#include "artemis/registration/odometry.hpp"
#include "artemis/semantics/active_brush.hpp"
#include "artemis/semantics/segmenter.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::pipeline {

// Semantics: every frame's camera image is segmented with the brush's prompts and fused into the
// map. The objects pointed to must outlive the run; segmenter == nullptr switches semantics off.
struct SemanticRunParams {
  semantics::Segmenter* segmenter = nullptr;
  semantics::ActiveBrush* brush = nullptr;
  const semantics::Vocabulary* vocabulary = nullptr;
  std::string camera;  // the segmented camera's name; empty (or absent from a frame): the frame's first camera
  bool write_distribution = false;             // prob_<class> per vertex in mesh.ply
  std::string segmenter_settings_json = "{}";  // recorded in semantics.json
  // Every segment_every-th frame of the range is segmented (the others are mapped without).
  int segment_every = 1;
  // Live use: the segmenter runs on a worker of its own and takes the newest frame whenever it is
  // free; the mapper never waits, and masks are fused (stage 1 late, by the cells of the frame's
  // points, and stage 2 with the frame's view) when they arrive. The frames observed then depend
  // on the machine's speed. Off (offline): every frame due is segmented, the next while one is mapped.
  bool realtime = false;
};

// What a run shows an observer (the live viewer) after each frame, on the mapping thread: the
// mapper may be read, not changed, until the call returns. The mesh's change log holds the voxels
// this frame re-meshed; `refinement` the voxels stage 2 looked at (their colours and classes may
// have changed). After the last frame, one more call with `finished` follows the final meshing.
struct FrameUpdate {
  const mapping::Mapper& mapper;
  std::size_t done = 0;  // frames of the range handled so far (mapped or skipped)
  std::size_t total = 0;
  std::size_t frame_index = 0;  // the recording's frame number
  Isometry3d T_W_L = Isometry3d::Identity();
  const mapping::RefinementStats* refinement = nullptr;  // nullptr: no stage 2 this frame
  const StageTimes& times;
  bool finished = false;
  // Tiles closed this frame that leave memory right after the observer (nullptr or empty: none):
  // an observer that keeps what it showed of them has their last state now.
  const std::set<mapping::TileKey>* leaving_tiles = nullptr;
};
using FrameObserver = std::function<void(const FrameUpdate&)>;

struct RunParams {
  mapping::MapperParams mapper;
  // Scan-to-map registration of every frame before it is mapped. Its prior is the recording's
  // relative motion, or a constant-velocity guess when use_recording_poses is false or the
  // recording has no poses (then refinement is the only source of poses).
  bool pose_refinement = false;
  bool use_recording_poses = true;
  registration::OdometryParams registration;
  // Motion compensation of each sweep from the motion estimate (prior motion since the last frame);
  // only for recordings with sweep start and end stamps.
  bool deskew = false;
  SemanticRunParams semantics;
  // Stage 2: texture refinement from each frame's camera image (frames without one are skipped).
  // With texture_holdout N > 0, every N-th frame of the range (the N-th, 2N-th, ...) is left out
  // of it, for `artemis eval texture` to render the mesh there.
  bool texture = false;
  int texture_holdout = 0;
  // Stage 2 of frame i runs after stage 1 of frame i + texture_delay (the last views after the final
  // meshing): the LiDAR meshes the ground and walls in front of the camera only as the vehicle
  // nears them, so a view refined at once misses much of what it shows, and the final mesh keeps
  // them uncoloured. Each view is still refined once; it waits with its scan, image and masks
  // (about 4 MB a frame at KITTI's size). A longer delay costs time (a view sees more mesh:
  // KITTI drive 0013's refinement median grew 12.3 / 16.6 / 22.0 / 26.2 ms at 0 / 5 / 10 / 15
  // frames), so the rest is left to the revisit below.
  int texture_delay = 5;
  // A textured view is kept after its refinement until frame i + texture_revisit, and then colours
  // the vertices added since that are still without colour and that it sees (Refinement::revisit):
  // surface meshed after every view that saw it had been refined. It waits with its image and
  // reference depth (about 2.3 MB a frame at KITTI's size); it costs in proportion to the vertices
  // added since (about 1.2 ms a KITTI-sized simulated frame at 60). 0, or a value not above
  // texture_delay: no revisit. Held-out PSNR (every 5th view), simulated street (200 frames):
  // delay 10 alone 20.53 dB; delay 5 with revisit 40 / 60 20.92 / 21.17 dB (plain averaging
  // 19.98 / 19.94); KITTI drive 0013 (frames 0-49): 13.10 / 13.20 / 13.11 dB. A revisit may give a
  // vertex its first colour before a nearer view still waiting is refined; keeping it to the
  // vertices every waiting view has been offered (up to scan i - texture_delay) measured 21.09 dB.
  int texture_revisit = 60;
  FrameObserver observer;  // optional
  // Checkpoints: after every checkpoint_every-th frame of the range (0: never), and when stopped,
  // the run's whole state goes to <out>/checkpoint.bin (atomically: a run killed while writing
  // keeps the one before); the finished run removes it. About the size of the map in memory plus
  // the views stage 2 holds (their images are read again on resume).
  int checkpoint_every = 100;
  // Written to <out>/checkpoint.json beside each checkpoint (nothing when empty): what the caller
  // needs to start the run again (the CLI: its flags and working folder).
  std::string resume_record_json;
  // Go on from <out>/checkpoint.bin, written by a run of the same recording with the same settings
  // (config_json must match), rather than from the range's first frame. The outputs then equal those
  // of a run that was never stopped.
  bool resume = false;
  // When set (by a signal handler, say), the run stops after the frame it is mapping, writes a
  // checkpoint and returns an error saying where it stopped and how to go on.
  const std::atomic<bool>* stop_requested = nullptr;
};

struct RunReport {
  std::size_t frames = 0;
  std::size_t frames_failed = 0;  // unreadable frames, logged and skipped
  std::size_t vertices = 0;
  std::size_t faces = 0;
  // Stages "read" (waiting for the frame: the next frame is read while one is mapped), ["register",]
  // ["segment",] "insert", ["fuse",] "mesh", ["constrain",] ["refine",] "total" (all but "segment")
  // per frame.
  StageTimes times;
  double finish_ms = 0.0;
  std::size_t faces_cut = 0;                 // by the semantic constraint, over the frames (not the final meshing)
  std::size_t points_in_vehicle_path = 0;    // returns dropped inside the vehicle's box (MapperParams)
  std::size_t points_carved = 0;             // kept points removed as free space (FreeSpaceCarver)
  std::size_t points_in_finished_tiles = 0;  // returns dropped: they fell in a tile already written
  std::size_t tiles_finished = 0;            // tiles written and dropped from memory during the run
  std::size_t tiles_reloaded = 0;            // finished tiles loaded back: the drive came back to them
  std::size_t tiles_in_memory = 0;           // at the last look for finished tiles
  std::size_t tiles_written = 0;             // tile files at the end (the finished and the rest)
  std::size_t dangling_faces = 0;            // stitching the tiles: faces whose corner no tile held
  std::size_t repeated_faces = 0;            // ... and faces two tiles held (one is written)
  std::size_t holes_filled = 0;              // small holes the final mesh closed (holeFillingFaces)
  std::size_t hole_faces = 0;                // ... with this many faces
  double peak_rss_mb = 0.0;
  std::uint64_t page_faults = 0;  // of the process, when the outputs were written (timing.hpp)
  std::vector<registration::FrameRegistration> registrations;  // one per mapped frame, with refinement
  std::vector<std::size_t> registered_frames;                  // their recording indices
  std::size_t registration_fallbacks = 0;                      // frames whose prior pose was kept
  std::size_t degenerate_frames = 0;                           // frames registered with a degenerate direction
  // With semantics: frames whose image was segmented and fused, and frames without an observation
  // (no image, no mask file, a segmenter error; each logged).
  std::size_t frames_observed = 0;
  std::size_t frames_unobserved = 0;
  std::size_t frames_not_due = 0;            // left out by segment_every
  std::size_t frames_busy = 0;               // real time: the segmenter was busy with an earlier frame
  std::size_t frames_late = 0;               // real time: masks arrived after the frame's view was refined
  std::size_t vertices_labelled = 0;         // mesh vertices with a class
  std::string segmented_camera;              // the camera whose images were segmented
  std::vector<std::size_t> held_out_frames;  // recording indices left out of texturing
  std::size_t frames_textured = 0;           // stage 2 updated colours from the frame's image
  std::size_t frames_semantic_refined = 0;   // stage 2 updated classes from the frame's masks
  // Checkpoints written by this process, their last size and slowest write; the range frame this
  // process resumed at (0: it started at the first).
  std::size_t checkpoints = 0;
  double checkpoint_mb = 0.0;
  double checkpoint_max_ms = 0.0;
  std::size_t resumed_at = 0;
};

// After each frame mapped: frames done of the range, and the report so far (tiles in memory...).
using ProgressFn = std::function<void(std::size_t done, std::size_t total, const RunReport& report)>;

// Runs the mapper over every frame of `dataset` and writes the outputs into `out`.
Result<RunReport> runPipeline(datasets::Dataset& dataset, const RunParams& params, const std::filesystem::path& out,
                              const std::string& config_json, const ProgressFn& progress = {});

// mesh.ply of a mapper's mesh (only the vertices faces use). With `semantics` (a mesh with prompted
// classes), the per-vertex class_id and confidence (and prob_* with `distribution`).
struct SemanticPlyOptions {
  const semantics::Vocabulary* vocabulary = nullptr;
  double confidence_lambda = 0.5;
  bool distribution = false;
};
Status writeMeshPly(const mapping::SemanticMesh& mesh, const std::filesystem::path& path,
                    const SemanticPlyOptions* semantics = nullptr);
// mesh_classes.ply: the mesh coloured by vertex class (grey where none).
Status writeClassColouredPly(const mapping::SemanticMesh& mesh, const semantics::Vocabulary& vocabulary,
                             const std::filesystem::path& path);

// timing.json text of a report.
std::string timingJson(const RunReport& report);

// semantics.json text of a run with semantics.
std::string semanticsJson(const RunReport& report, const RunParams& params);

// registration.json text: {"frames": [{"frame", "fallback", "reason", "iterations",
// "correspondences", "rms_m", "correction_m", "correction_deg", "first_distance_m",
// "degenerate_directions", "source_points", "ms", "icp_ms", "map_ms"}, ...], "fallbacks": N,
// "degenerate_frames": N}.
std::string registrationJson(const RunReport& report);

}  // namespace artemis::pipeline
