// What the flags of `artemis run` settle against the recording: pose refinement, and config.json.
#include "run_flags.hpp"

namespace artemis::cli {

Result<bool> resolvePoseRefinement(const RunFlags& f, const datasets::Dataset& dataset) {
  const bool no_poses = f.dataset.poses == "none" || !dataset.hasPoses();
  if (f.pose_refinement == "off") {
    if (no_poses) {
      return invalidArgument(
          f.dataset.poses == "none"
              ? "--poses none needs --pose-refinement on: registration is then the only source of poses"
              : dataset.root().string() + " has no poses: --pose-refinement off cannot map it");
    }
    return false;
  }
  if (f.pose_refinement == "on") return true;
  if (no_poses) return true;
  return dataset.format() == "kitti-raw" && f.dataset.poses.empty();
}

nlohmann::ordered_json configJson(const RunFlags& f, const std::string& dataset_path) {
  const auto& m = f.params.mapper;
  nlohmann::ordered_json semantic = nullptr;
  if (!f.segmenter.empty()) {
    semantic = {{"queries", f.queries},
                {"segmenter", f.segmenter},
                {"segmenter_noise", f.segmenter_noise},
                {"seed", f.seed},
                {"masks", f.masks},
                {"sim_gt", f.sim_gt},
                {"model", f.model},
                {"model_config", f.model_config},
                {"segment_every", f.params.semantics.segment_every},
                {"segment_mode", f.params.semantics.realtime ? "realtime" : "offline"},
                {"vocabulary", f.vocabulary.empty() ? "semantickitti" : f.vocabulary},
                {"aliases", f.aliases.empty() ? "built-in" : f.aliases},
                {"sigma_depth_m", m.semantics.sigma_depth_m},
                {"depth_window_px", m.semantics.depth_window_px},
                {"silhouette_radius_px", m.semantics.geometry.silhouettes.radius_px},
                {"background_score", m.semantics.background_score},
                {"confidence_lambda", m.semantics.confidence_lambda},
                {"voxel_prior", m.semantics.voxel_prior},
                {"semantic_refinement", m.refinement.semantic_refinement},
                {"mask_floor", m.refinement.mask_floor},
                {"mask_border_px", m.refinement.mask_border_px},
                {"stage_one_weight", m.refinement.stage_one_weight}};
  }
  nlohmann::ordered_json j = {
      {"dataset",
       {{"path", dataset_path},
        {"format", f.dataset.format},
        {"frames", f.dataset.frames.empty() ? "all" : f.dataset.frames},
        {"min_range_m", f.dataset.min_range_m},
        {"max_range_m", f.dataset.max_range_m},
        {"vertical_correction", f.dataset.vertical_correction},
        {"poses", f.dataset.poses.empty() ? "recording" : f.dataset.poses}}},
      {"registration",
       {{"pose_refinement", f.params.pose_refinement},
        {"prior", f.params.use_recording_poses ? "recording motion" : "constant velocity"},
        {"deskew", f.params.deskew},
        {"source_voxel_m", f.params.registration.source_voxel_m},
        {"map_voxel_m", f.params.registration.map.voxel_size_m},
        {"map_subdivisions", f.params.registration.map.subdivisions},
        {"initial_distance_m", f.params.registration.initial_distance_m},
        {"min_distance_m", f.params.registration.min_distance_m},
        {"fine_distance_m", f.params.registration.icp.min_distance_m}}},
      {"voxels", {{"voxel_size_m", m.voxels.voxel_size_m}, {"subdivisions", m.voxels.subdivisions}}},
      {"mesher",
       {{"rim_m", m.mesher.rim_m},
        {"max_edge_m", m.mesher.max_edge_m},
        {"max_edge_nonplanar_m", m.mesher.max_edge_nonplanar_m},
        {"max_edge_upright_m", m.mesher.max_edge_upright_m},
        {"min_angle_deg", m.mesher.min_angle_deg},
        {"max_plane_angle_deg", m.mesher.max_plane_angle_deg},
        {"nonplanar_ratio", m.mesher.nonplanar_ratio},
        {"linear_ratio", m.mesher.linear_ratio}}},
      {"semantic_constraint",
       {{"on", m.constraint.enabled},
        {"lambda_sem", m.constraint.lambda_sem},
        {"lambda_smooth", m.constraint.lambda_smooth},
        {"temperature", m.constraint.temperature},
        {"max_sweeps", m.constraint.max_sweeps},
        {"steps", m.constraint.steps},
        {"tolerance", m.constraint.tolerance},
        {"max_step_m", m.constraint.max_step_m},
        {"max_offset_m", m.constraint.max_offset_m},
        {"cut_similarity", m.constraint.cut_similarity},
        {"cut_depth_gap_m", m.constraint.cut_depth_gap_m}}},
      {"free_space",
       {{"on", m.free_space.enabled},
        {"max_range_m", m.free_space.max_range_m},
        {"lateral_m", m.free_space.lateral_m},
        {"margin_m", m.free_space.margin_m},
        {"min_return_range_m", m.free_space.min_return_range_m},
        {"lateral_per_m", m.free_space.lateral_per_m},
        {"margin_per_m", m.free_space.margin_per_m},
        {"beside_margin_m", m.free_space.beside_margin_m},
        {"min_incidence_cos", m.free_space.min_incidence_cos},
        {"confirm_hits", m.free_space.confirm_hits},
        {"confirm_span_frames", m.free_space.confirm_span_frames},
        {"min_misses", m.free_space.min_misses},
        {"misses_per_hit", m.free_space.misses_per_hit},
        {"lookback_frames", m.free_space.lookback_frames},
        {"young_lookback_frames", m.free_space.young_lookback_frames},
        {"young_stride", m.free_space.young_stride},
        {"recent_frames", m.free_space.recent_frames},
        {"old_voxel_stride", m.free_space.old_voxel_stride},
        {"companions", m.free_space.companions}}},
      {"hole_filling",
       {{"on", m.holes.enabled},
        {"max_loop_edges", m.holes.max_loop_edges},
        {"max_plane_distance_m", m.holes.max_plane_distance_m},
        {"min_normal_agreement", m.holes.min_normal_agreement}}},
      {"tiles",
       {{"on", m.tiles.enabled},
        {"edge_m", m.tiles.edge_m},
        {"evict_distance_m", m.tiles.evict_distance_m},
        {"check_every", m.tiles.check_every}}},
      {"vehicle_box_m",
       m.vehicle_box_L.isEmpty()
           ? nlohmann::json(nullptr)
           : nlohmann::json{m.vehicle_box_L.min().x(), m.vehicle_box_L.max().x(), m.vehicle_box_L.min().y(),
                            m.vehicle_box_L.max().y(), m.vehicle_box_L.min().z(), m.vehicle_box_L.max().z()}},
      {"remesh_growth", m.remesh_growth},
      {"remesh_min_new", m.remesh_min_new},
      {"first_mesh_points", m.first_mesh_points},
      {"threads", m.threads},
      {"semantics", semantic},
      {"texture",
       {{"on", f.params.texture},
        {"holdout", f.params.texture_holdout},
        {"delay_frames", f.params.texture_delay},
        {"revisit_frames", f.params.texture_revisit},
        {"range_m", m.refinement.max_range_m},
        {"reliability", m.refinement.reliability},
        {"sigma_photo", m.refinement.sigma_photo},
        {"sigma_geom", m.refinement.sigma_geom},
        {"depth_epsilon_m", m.refinement.depth_epsilon_m},
        {"min_reliability", m.refinement.min_reliability},
        {"sigma_obs", m.refinement.sigma_obs},
        {"exposure_gain", m.refinement.exposure_gain},
        {"lidar_window_px", m.refinement.lidar_window_px}}}};
  // A bag's topics and camera calibration, so that evaluations and pictures open it as the run did.
  const auto& bag = f.dataset.bag_topics;
  if (!bag.lidar.empty() || !bag.image.empty() || !bag.imu.empty() || !bag.odometry.empty() ||
      !f.dataset.bag_calib.empty() || f.dataset.bag_time_offset_s || f.dataset.bag_sweep_period_s > 0.0) {
    j["dataset"]["bag"] = {{"lidar_topic", bag.lidar},     {"image_topic", bag.image},
                           {"imu_topic", bag.imu},         {"odom_topic", bag.odometry},
                           {"calib", f.dataset.bag_calib}, {"sweep_period_s", f.dataset.bag_sweep_period_s}};
    if (f.dataset.bag_time_offset_s) j["dataset"]["bag"]["time_offset_s"] = *f.dataset.bag_time_offset_s;
  }
  return j;
}

}  // namespace artemis::cli
