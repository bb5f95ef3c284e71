// The options of `artemis run`, registered in the order --help lists them, and --vehicle-box's parser.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include <fmt/format.h>

#include "flag_checks.hpp"
#include "run_flags.hpp"

namespace artemis::cli {
namespace {

void addFreeSpaceFlags(CLI::App& cmd, mapping::FreeSpaceParams& fs) {
  cmd.add_flag_callback(
      "--no-free-space", [&fs] { fs.enabled = false; },
      "Keep every point the LiDAR returned, even where later rays saw through it (moving traffic leaves trails)");
  cmd.add_option("--free-space-range", fs.max_range_m,
                 "Free space: test map points up to this far from the sensor against each scan's rays (m)")
      ->capture_default_str()
      ->check(within(1.0, 500.0));
  cmd.add_option("--free-space-lookback", fs.lookback_frames,
                 "Free space: test the points each frame adds against the rays of this many frames before (more: "
                 "less of what oncoming traffic leaves behind, for more time and memory a frame)")
      ->capture_default_str()
      ->check(CLI::Range(0, 30));
  cmd.add_option("--free-space-young-lookback", fs.young_lookback_frames,
                 "Free space: the points each frame adds where the map had nothing a few frames before are also "
                 "looked past with the rays of up to this many frames before, of every --free-space-young-stride-th "
                 "(what passing traffic leaves where earlier scans saw the road; 0: off)")
      ->capture_default_str()
      ->check(CLI::Range(0, 60));
  cmd.add_option("--free-space-young-stride", fs.young_stride,
                 "Free space: of the frames before the last --free-space-lookback, keep the rays of every N-th for the "
                 "young voxels' test")
      ->capture_default_str()
      ->check(CLI::Range(1, 60));
  cmd.add_option("--free-space-stride", fs.old_voxel_stride,
                 "Free space: test the map's older points in one voxel of every N each frame, in turn (fewer tests a "
                 "frame; a trail takes a few frames longer to go)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
}

void addMapperFlags(CLI::App& cmd, RunFlags& f) {
  auto& m = f.params.mapper;
  // Each setting's range: what the method can work with, not what a good map needs.
  cmd.add_option("--voxel-size", m.voxels.voxel_size_m, "Voxel size (m)")
      ->capture_default_str()
      ->check(within(0.05, 5.0));
  cmd.add_option("--subdivisions", m.voxels.subdivisions,
                 "Sub-cells per voxel axis; one point kept per sub-cell (1..8)")
      ->capture_default_str()
      ->check(CLI::Range(1, 8));
  cmd.add_option("--max-edge", m.mesher.max_edge_m, "Longest face edge on planar voxels (m)")
      ->capture_default_str()
      ->check(within(0.01, 10.0));
  cmd.add_option("--max-edge-upright", m.mesher.max_edge_upright_m,
                 "Longest face edge on planar voxels that stand upright (walls, hedges, car sides), where the "
                 "beams lie closer than on the ground: a longer edge spans a gap (m; --max-edge if that is shorter)")
      ->capture_default_str()
      ->check(within(0.01, 10.0));
  cmd.add_option("--remesh-growth", m.remesh_growth,
                 "Re-mesh a voxel once its points grew by this share since it was last meshed")
      ->capture_default_str()
      ->check(within(0.01, 100.0));
  cmd.add_option("--first-mesh-points", m.first_mesh_points, "Points a voxel needs before it is first meshed")
      ->capture_default_str()
      ->check(within(3, 1000000));
  cmd.add_option("--rim", m.mesher.rim_m, "Neighbour points this close to a voxel join its triangulation (m)")
      ->capture_default_str()
      ->check(within(0.0, 2.0));
  cmd.add_option("--threads", m.threads, "Worker threads (0: all cores)")
      ->capture_default_str()
      ->check(within(0, 1024));
  addFreeSpaceFlags(cmd, m.free_space);
  cmd.add_flag_callback(
      "--no-hole-filling", [&holes = m.holes] { holes.enabled = false; },
      "Leave the final mesh's small holes open (the cracks along voxel borders on sparse ground)");
  cmd.add_option("--hole-max-edges", m.holes.max_loop_edges,
                 "Hole filling: close holes whose outline has at most this many edges")
      ->capture_default_str()
      ->check(CLI::Range(3, 64));
  cmd.add_flag_callback(
      "--no-tiles", [&tiles = m.tiles] { tiles.enabled = false; },
      "Keep the whole map in memory (a long drive's memory then grows with the drive)");
  cmd.add_option("--tile-edge", m.tiles.edge_m,
                 "Tiles: the map is cut into square columns of this edge, rounded to whole 16-voxel blocks, one at "
                 "least (m)")
      ->capture_default_str()
      ->check(within(0.8, 10000.0));
  cmd.add_option("--evict-distance", m.tiles.evict_distance_m,
                 "Tiles: a tile this far from the sensor and from every view still to be textured is written to "
                 "OUT/tiles and leaves memory; returns that later fall in it are dropped (m; more than "
                 "--texture-range)")
      ->capture_default_str()
      ->check(within(1.0, 1e6));
  cmd.add_option("--evict-every", m.tiles.check_every,
                 "Tiles: look for tiles to write and drop after every N frames (finishing tiles costs a few hundred "
                 "ms on 2 cores; rare looks keep it out of most frames)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd.add_option("--vehicle-box", f.vehicle_box,
                 "The vehicle's body in the LiDAR frame: returns inside it at the current or an earlier pose "
                 "(a car following in the same lane) are dropped. kitti (KITTI's car and the simulator's), off, "
                 "or x0,x1,y0,y1,z0,z1 in m")
      ->capture_default_str();
}

void addConstraintFlags(CLI::App& cmd, mapping::SemanticConstraintParams& c) {
  cmd.add_flag_callback(
      "--no-semantic-constraint", [&constraint = c] { constraint.enabled = false; },
      "Keep the vertices where the LiDAR put them and the faces the mesher made: no stage 1d (eq. 2-8)");
  cmd.add_option("--lambda-smooth", c.lambda_smooth, "Semantic constraint: weight of E_smoothness (eq. 2)")
      ->capture_default_str()
      ->check(within(0.0, 1000.0));
  cmd.add_option("--lambda-sem", c.lambda_sem, "Semantic constraint: weight of E_semantic (eq. 2)")
      ->capture_default_str()
      ->check(within(0.0, 1000.0));
  cmd.add_option("--semantic-temperature", c.temperature, "Semantic constraint: tau of eq. 5")
      ->capture_default_str()
      ->check(within(0.0, 1000.0));
  cmd.add_option("--constraint-sweeps", c.max_sweeps, "Semantic constraint: most Gauss-Seidel sweeps a frame")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd.add_option("--max-vertex-offset", c.max_offset_m,
                 "Semantic constraint: farthest a vertex may move from its LiDAR return (m)")
      ->capture_default_str()
      ->check(within(0.0, 2.0));
  cmd.add_option("--cut-similarity", c.cut_similarity,
                 "Semantic constraint: cut faces whose edge has semantic similarity (eq. 5) below this and spans a "
                 "depth gap (0: never cut)")
      ->capture_default_str()
      ->check(within(0.0, 1.0));
  cmd.add_option("--cut-depth-gap", c.cut_depth_gap_m,
                 "Semantic constraint: the depth gap along the viewing ray an edge must span to be cut (m)")
      ->capture_default_str()
      ->check(within(0.0, 10.0));
}

void addRegistrationFlags(CLI::App& cmd, RunFlags& f) {
  cmd.add_option("--pose-refinement", f.pose_refinement,
                 "Scan-to-map registration of every frame before mapping: on, off, or auto (on for GPS/IMU "
                 "poses such as KITTI raw's, and without poses)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd.add_flag("--deskew", f.params.deskew,
               "Motion-compensate each sweep from the motion estimate (recordings with sweep start/end "
               "stamps, such as KITTI raw)");
  auto& r = f.params.registration;
  cmd.add_option("--registration-voxel", r.source_voxel_m,
                 "Registration keeps one scan point per cell of this size (m)")
      ->capture_default_str()
      ->check(within(0.05, 10.0));
  cmd.add_option("--registration-fine-distance", r.icp.min_distance_m,
                 "Correspondence distance of registration's finest stage (m)")
      ->capture_default_str()
      ->check(within(0.01, 10.0));
}

void addTextureFlags(CLI::App& cmd, RunFlags& f) {
  cmd.add_option(
         "--texture", f.texture,
         "Stage 2 texture refinement from the camera images: auto (on when the recording has a camera), on, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd.add_option("--texture-holdout", f.params.texture_holdout,
                 "Leave every N-th frame's image out of texturing (for artemis eval texture); 0: none")
      ->capture_default_str()
      ->check(within(0, 1000000));
  cmd.add_option("--texture-range", f.params.mapper.refinement.max_range_m,
                 "Stage 2: surface farther than this from the camera is not textured or refined (m)")
      ->capture_default_str()
      ->check(within(1.0, 130.0));
  cmd.add_option("--texture-delay", f.params.texture_delay,
                 "Refine each frame's image this many frames after its scan was mapped, once later scans have "
                 "meshed the ground and walls in front of the camera (0: at once)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  cmd.add_option("--texture-revisit", f.params.texture_revisit,
                 "Keep each textured image until this many frames after its scan, then colour with it what the "
                 "map gained since its refinement (0 or not above --texture-delay: no revisit)")
      ->capture_default_str()
      ->check(CLI::Range(0, 300));
  auto& rp = f.params.mapper.refinement;
  cmd.add_flag(
      "--no-reliability", [&refinement = rp](std::int64_t) { refinement.reliability = false; },
      "Texture: plain averaging of every view (no reliability W, eq. 9-11)");
  cmd.add_option("--sigma-photo", rp.sigma_photo, "Texture: sigma_photo of eq. 9 (linear RGB)")
      ->capture_default_str()
      ->check(within(1e-4, 100.0));
  cmd.add_option("--sigma-geom", rp.sigma_geom, "Texture: sigma_geom of eq. 9 (relative depth)")
      ->capture_default_str()
      ->check(within(1e-4, 100.0));
  cmd.add_option("--lidar-window", rp.lidar_window_px,
                 "Refinement: the reference depth is the nearer of the mesh's z-buffer and the frame's LiDAR depth "
                 "within this many pixels; -1: the z-buffer alone")
      ->capture_default_str()
      ->check(CLI::Range(-1, 16));
}

void addSegmenterFlags(CLI::App& cmd, RunFlags& f) {
  cmd.add_option("-q,--query", f.queries,
                 "Classes to segment and fuse, in words (\"cars and buildings\", \"vegetation\"); repeat for more. "
                 "Needs --segmenter")
      ->take_all();
  cmd.add_option("--segmenter", f.segmenter,
                 "dnn: a dense segmentation network on the CPU (--model, --model-config); onnx: instance models "
                 "through ONNX Runtime, with CLIP an open vocabulary (--model-config, see README); sim: the "
                 "simulator's ground truth with noise (artemis sim output); maskfile: masks an external segmenter "
                 "wrote (--masks)")
      ->check(CLI::IsMember({"dnn", "onnx", "sim", "maskfile"}));
  cmd.add_option("--model", f.model, "dnn: the network's weights (Torch7, ONNX, Caffe, TensorFlow)");
  cmd.add_option("--model-config", f.model_config,
                 "dnn, onnx: how to run the models (JSON, see README; data/models/enet-cityscapes.json)");
  cmd.add_option("--segment-every", f.params.semantics.segment_every, "Segment every Nth frame with an image (1: all)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd.add_flag("--realtime-segmentation", f.params.semantics.realtime,
               "Never wait for the segmenter: it takes the newest frame whenever it is free, and its masks are fused "
               "when they arrive (live use; the frames observed depend on the machine's speed)");
  cmd.add_option("--segmenter-noise", f.segmenter_noise, "sim: none, standard or heavy")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "standard", "heavy"}));
  cmd.add_option("--seed", f.seed, "sim: seed of the segmenter's noise")->capture_default_str();
  cmd.add_option("--masks", f.masks, "maskfile: folder of NNNNNN.png + NNNNNN.json per frame (see README)");
  cmd.add_option("--sim-gt", f.sim_gt, "sim: the simulator's gt/ folder (default: found beside the recording)");
}

void addLiveViewerFlags(CLI::App& cmd, RunFlags& f) {
  cmd.add_flag(
      "--viewer", f.viewer,
      "Serve the live browser viewer while mapping (http://127.0.0.1:8080/ unless --viewer-port/--viewer-host)");
  addViewerFlags(cmd, f.viewer_flags, "viewer-");
  cmd.add_option("--viewer-linger", f.viewer_linger_s,
                 "Viewer: seconds to keep serving the finished map (default: until Ctrl-C)")
      ->check(within(0.0, 1e7));
}

// The vocabulary, stage 1's fusion (eq. 1) and stage 2's semantic refinement (eq. 12-13).
void addSemanticFlags(CLI::App& cmd, RunFlags& f) {
  auto& m = f.params.mapper;
  auto& rp = m.refinement;
  cmd.add_option("--vocabulary", f.vocabulary, "Class vocabulary JSON (default: SemanticKITTI's 19 classes)");
  cmd.add_option("--aliases", f.aliases, "Alias table JSON extending the built-in one (see artemis ground)");
  cmd.add_flag("--semantic-distribution", f.params.semantics.write_distribution,
               "Also write each vertex's class distribution (prob_<class>) into mesh.ply");
  auto& sf = m.semantics;
  cmd.add_option("--sigma-depth", sf.sigma_depth_m, "sigma_d of eq. 1: depth-uncertainty scale (m)")
      ->capture_default_str()
      ->check(within(1e-3, 100.0));
  cmd.add_flag(
      "--no-geometric-prior", [&fusion = sf](std::int64_t) { fusion.geometry.enabled = false; },
      "Dense segmenters: take the pixels' class probabilities as they are, without what the map's geometry "
      "(height above the ground, surface orientation) says of each class");
  cmd.add_option("--silhouette-radius", sf.geometry.silhouettes.radius_px,
                 "Object classes (vehicles, people): a point farther than 1 m + 10 % behind a return of the same "
                 "class within this many pixels observes nothing, in fusion and refinement: the mask spilled past "
                 "the object's silhouette (0: off)")
      ->capture_default_str()
      ->check(CLI::Range(0, 256));
  cmd.add_option("--voxel-prior", sf.voxel_prior,
                 "Weight of a vertex's voxel (0.4 m) distribution against its own cell's evidence")
      ->capture_default_str()
      ->check(within(1e-3, 1e6));
  cmd.add_option("--background-score", sf.background_score,
                 "Confidence of a pixel outside every mask (\"none of the prompted classes\")")
      ->capture_default_str()
      ->check(within(0.0, 1.0));
  cmd.add_flag(
      "--no-semantic-refinement", [&refinement = rp](std::int64_t) { refinement.semantic_refinement = false; },
      "Keep stage 1's classes: no per-vertex log-probability update from the views (eq. 12-13)");
  cmd.add_option("--mask-floor", rp.mask_floor, "Semantic refinement: the least P_mask (eq. 13)")
      ->capture_default_str()
      ->check(within(1e-6, 0.5));
  cmd.add_option("--stage-one-weight", rp.stage_one_weight,
                 "Semantic refinement: how many views stage 1's distribution counts as in the read-out")
      ->capture_default_str()
      ->check(within(1e-3, 1e6));
  cmd.add_option("--mask-border", rp.mask_border_px,
                 "Semantic refinement: a vertex whose pixel is this close to another mask observes nothing (px)")
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
}

}  // namespace

void addRunFlags(CLI::App& cmd, RunFlags& flags) {
  flags.dataset.addTo(cmd, /*with_poses=*/true, /*poses_none=*/true);
  cmd.add_option("-o,--out", flags.out, "Output folder")->capture_default_str();
  cmd.add_option("--checkpoint-every", flags.params.checkpoint_every,
                 "Write the run's state to OUT/checkpoint.bin after every N frames (0: never), and on Ctrl-C; "
                 "a stopped or killed run goes on with --resume OUT")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--resume", flags.resume,
                 "Go on with the run in this output folder from its last checkpoint, with the settings it was "
                 "started with (no other flags); its outputs equal those of a run never stopped");
  addMapperFlags(cmd, flags);
  addConstraintFlags(cmd, flags.params.mapper.constraint);
  addRegistrationFlags(cmd, flags);
  addTextureFlags(cmd, flags);
  addSegmenterFlags(cmd, flags);
  addLiveViewerFlags(cmd, flags);
  addSemanticFlags(cmd, flags);
}

Status checkTileFlags(const mapping::MapperParams& m) {
  if (!m.tiles.enabled) return Status::ok();
  if (!(m.tiles.evict_distance_m > m.refinement.max_range_m)) {
    return invalidArgument(fmt::format(
        "--evict-distance {} must exceed --texture-range ({} m): a view could still texture a tile already written",
        m.tiles.evict_distance_m, m.refinement.max_range_m));
  }
  return Status::ok();
}

Result<Eigen::AlignedBox3f> parseVehicleBox(const std::string& text) {
  if (text == "off") return Eigen::AlignedBox3f();
  if (text == "kitti")
    // From 0.10 m above the road (the LiDAR is 1.73 m up): what a car driving ahead leaves below its
    // bumper goes when this one drives through, as does the strip below a following car's bumper
    // that a floor at 0.18 m left standing in the lane as fins; the road's returns (a few cm of
    // noise, 5 cm more at the box's ends under a pitch of a degree) stay.
    return Eigen::AlignedBox3f(Eigen::Vector3f(-2.7f, -0.8f, -1.63f), Eigen::Vector3f(1.7f, 0.8f, 0.0f));
  std::vector<float> v;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stof(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      return invalidArgument("--vehicle-box: '" + item +
                             "' is not a number (expected kitti, off or x0,x1,y0,y1,z0,z1)");
    }
  }
  if (v.size() != 6 || !(v[0] < v[1]) || !(v[2] < v[3]) || !(v[4] < v[5]) ||
      !std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); })) {
    return invalidArgument(
        "--vehicle-box '" + text +
        "': expected kitti, off or six finite numbers x0,x1,y0,y1,z0,z1 with x0 < x1, y0 < y1, z0 < z1");
  }
  return Eigen::AlignedBox3f(Eigen::Vector3f(v[0], v[2], v[4]), Eigen::Vector3f(v[1], v[3], v[5]));
}

}  // namespace artemis::cli
