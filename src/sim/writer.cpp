#include "artemis/sim/writer.hpp"

#include <fmt/format.h>

#include <tbb/parallel_invoke.h>
#include <bit>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>

#include "artemis/core/timer.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/io/png.hpp"
#include "artemis/sim/simulator.hpp"
#include "colour.hpp"

namespace artemis::sim {

namespace fs = std::filesystem;
using Eigen::Vector3d;

static_assert(std::endian::native == std::endian::little, "KITTI files are little-endian");

namespace {

fs::path sequenceDir(const fs::path& out) {
  return out / "sequences" / "00";
}
std::string stem(int frame) {
  return fmt::format("{:06d}", frame);
}

Status writeText(const fs::path& path, const std::string& text) {
  return io::writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

template <typename T>
Status writeVector(const fs::path& path, const std::vector<T>& values) {
  return io::writeFileAtomic(path, std::as_bytes(std::span(values.data(), values.size())));
}

Status makeDirs(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return ioError(fmt::format("{}: cannot create folder: {}", dir.string(), ec.message()));
  return Status::ok();
}

std::string numbers(const std::array<double, 12>& v) {
  return fmt::format("{:.12e}", fmt::join(v, " "));
}

std::uint8_t srgb8(float linear) {
  return static_cast<std::uint8_t>(std::lround(255.0 * detail::srgbEncode(static_cast<double>(linear))));
}

ImageU8 colourClasses(const ImageU16& classes) {
  ImageU8 rgb(classes.width(), classes.height(), 3);
  for (int v = 0; v < classes.height(); ++v) {
    for (int u = 0; u < classes.width(); ++u) {
      const auto c = classColor(classes.at(u, v));
      for (int k = 0; k < 3; ++k) rgb.at(u, v, k) = c[static_cast<std::size_t>(k)];
    }
  }
  return rgb;
}

Status writeMesh(const Simulator& sim, const fs::path& path) {
  const Scene& scene = sim.scene();
  const SceneMesh& m = scene.mesh;
  const Isometry3d T_W_S = sim.T_S_W().inverse();
  std::vector<float> xyz(3 * m.vertices.size());
  std::vector<std::uint8_t> rgb(3 * m.vertices.size(), 0);
  std::vector<bool> coloured(m.vertices.size(), false);
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const Vector3d p_W = T_W_S * m.vertices[i].cast<double>();
    for (int k = 0; k < 3; ++k) xyz[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(p_W(k));
  }
  std::vector<std::uint32_t> triangles(3 * m.faceCount());
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = m.triangles[f][k];
      triangles[3 * f + k] = v;
      if (coloured[v]) continue;  // a vertex takes the albedo of the first face that uses it
      coloured[v] = true;
      const Eigen::Vector3f a = scene.albedo(f, m.vertices[v].cast<double>());
      for (int c = 0; c < 3; ++c) rgb[3 * v + static_cast<std::size_t>(c)] = srgb8(a(c));
    }
  }
  io::PlyData ply = io::makePlyMesh({.xyz = &xyz, .normals = nullptr, .rgb = &rgb, .triangles = &triangles});
  ply.comments.push_back("ARTEMIS simulated street: ground-truth surface in the world frame (first LiDAR pose)");
  ply.comments.push_back("vertex red/green/blue: albedo, sRGB; face class_id: SemanticKITTI class; instance_id");
  if (Status s = ply.setScalar("face", "class_id", m.face_class); !s.isOk()) return s;
  if (Status s = ply.setScalar("face", "instance_id", m.face_instance); !s.isOk()) return s;
  return io::writePly(path, ply);
}

const char* motionName(MotionKind kind) {
  switch (kind) {
    case MotionKind::kFollow: return "follow";
    case MotionKind::kLine: return "line";
    case MotionKind::kPace: return "pace";
    case MotionKind::kCross: return "cross";
  }
  return "?";
}

// The movers and their motions (traffic.hpp), with their poses at the first frame.
nlohmann::ordered_json moversJson(const Simulator& sim) {
  nlohmann::ordered_json movers = nlohmann::ordered_json::array();
  const std::vector<Isometry3d> T_S_M = sim.moverPoses(0);
  for (std::size_t i = 0; i < sim.movers().size(); ++i) {
    const Mover& m = sim.movers()[i];
    const MoverMotion& mo = m.motion;
    nlohmann::ordered_json motion = {{"kind", motionName(mo.kind)}};
    if (mo.kind == MotionKind::kFollow) {
      motion.update({{"gap_m", mo.gap_m},
                     {"gap_variation_m", mo.gap_variation_m},
                     {"gap_period_s", mo.gap_period_s},
                     {"phase_rad", mo.phase_rad}});
    } else {
      motion.update({{"x0", mo.x0},
                     {"x1", mo.x1},
                     {"y0", mo.y0},
                     {"y1", mo.y1},
                     {"z", mo.z},
                     {"speed_mps", mo.speed_mps},
                     {"t0_s", mo.t0_s}});
    }
    const Eigen::Vector3d p = T_S_M[i].translation();
    movers.push_back({{"instance_id", m.instance_id},
                      {"kind", m.kind},
                      {"class_id", m.class_id},
                      {"label_id", m.moving_id},
                      {"footprint_m", {2 * m.half_extent_m.x(), 2 * m.half_extent_m.y()}},
                      {"position_S_at_frame_0", {p.x(), p.y(), p.z()}},
                      {"motion", motion}});
  }
  return movers;
}

}  // namespace

std::string sceneJson(const Simulator& sim) {
  using nlohmann::ordered_json;
  const Scene& scene = sim.scene();
  ordered_json j;
  j["generator"] = "artemis sim";
  j["params"] = ordered_json::parse(paramsToJson(sim.params()));
  j["street_length_m"] = scene.length_m;
  j["frames"] = "world W = first LiDAR pose; scene S: x along the street, y left, z up, road at z = 0";
  j["T_S_W"] = toRowMajor3x4(sim.T_S_W());
  j["triangles"] = scene.mesh.faceCount();
  ordered_json classes = ordered_json::array();
  for (const ClassCount& c : countClasses(scene)) {
    classes.push_back({{"class_id", c.class_id},
                       {"name", className(c.class_id)},
                       {"instances", c.objects},
                       {"triangles", c.triangles}});
  }
  j["classes"] = classes;
  ordered_json objects = ordered_json::array();
  for (const SceneObject& o : scene.objects) {
    objects.push_back({{"instance_id", o.instance_id},
                       {"kind", o.kind},
                       {"class_id", o.class_id},
                       {"position_S", {o.position_S.x(), o.position_S.y(), o.position_S.z()}},
                       {"yaw_rad", o.yaw_rad},
                       {"size_m", {o.size_m.x(), o.size_m.y(), o.size_m.z()}},
                       {"color", {o.color.x(), o.color.y(), o.color.z()}},
                       {"variant", o.variant}});
  }
  j["objects"] = objects;
  if (!sim.movers().empty()) j["movers"] = moversJson(sim);
  return j.dump(1) + "\n";
}

Status writeGroundTruth(const Simulator& sim, const fs::path& out) {
  for (const fs::path& dir :
       {out / "gt" / "semantic_2", out / "gt" / "instance_2", out / "gt" / "depth_2", out / "preview"}) {
    if (Status s = makeDirs(dir); !s.isOk()) return s;
  }
  if (Status s = writeMesh(sim, out / "gt" / "mesh.ply"); !s.isOk()) return s;
  return writeText(out / "scene.json", sceneJson(sim));
}

Status writeStatic(const Simulator& sim, const fs::path& out) {
  const fs::path seq = sequenceDir(out);
  for (const fs::path& dir : {seq / "velodyne", seq / "labels", seq / "image_2", out / "poses"}) {
    if (Status s = makeDirs(dir); !s.isOk()) return s;
  }
  const KittiCalibration& c = kittiCalibration();
  const std::string calib = fmt::format("P0: {}\nP1: {}\nP2: {}\nP3: {}\nTr: {}\n", numbers(c.P0), numbers(c.P1),
                                        numbers(c.P2), numbers(c.P3), numbers(c.Tr));
  if (Status s = writeText(seq / "calib.txt", calib); !s.isOk()) return s;

  std::string times;
  std::string poses;
  const Isometry3d Tr = isometryFromRowMajor3x4(c.Tr).value();
  for (int k = 0; k < sim.frames(); ++k) {
    times += fmt::format("{:.6e}\n", sim.stamp_s(k));
    // KITTI odometry keeps camera-0 poses: P = Tr * T_W_L * inv(Tr).
    poses += formatRowMajor3x4(Tr * sim.T_W_L(k) * Tr.inverse()) + "\n";
  }
  if (Status s = writeText(seq / "times.txt", times); !s.isOk()) return s;
  if (Status s = writeText(out / "poses" / "00.txt", poses); !s.isOk()) return s;
  return writeGroundTruth(sim, out);
}

Status writeFrameTruth(const Simulator& sim, const fs::path& out, int frame, const CameraImages& images) {
  const std::string name = stem(frame);
  Status results[3];
  tbb::parallel_invoke([&] { results[0] = io::writePng(out / "gt" / "semantic_2" / (name + ".png"), images.semantic); },
                       [&] { results[1] = io::writePng(out / "gt" / "instance_2" / (name + ".png"), images.instance); },
                       [&] { results[2] = io::writePng(out / "gt" / "depth_2" / (name + ".png"), images.depth_mm); });
  for (const Status& s : results) {
    if (!s.isOk()) return s;
  }
  if (frame == 0 || frame == sim.frames() / 2) {
    return io::writePng(out / "preview" / (name + "_class.png"), colourClasses(images.semantic));
  }
  return Status::ok();
}

Status writeFrame(const Simulator& sim, const fs::path& out, int frame, SimReport* report) {
  const fs::path seq = sequenceDir(out);
  const std::string name = stem(frame);
  Stopwatch watch;
  const LidarScan scan = sim.scan(frame);
  const double lidar_ms = watch.elapsedMs();
  watch.reset();
  const CameraImages images = sim.render(frame);
  const double camera_ms = watch.elapsedMs();
  watch.reset();
  std::vector<float> xyzi(4 * scan.points_L.size());
  for (std::size_t i = 0; i < scan.points_L.size(); ++i) {
    std::memcpy(&xyzi[4 * i], scan.points_L[i].data(), 4 * sizeof(float));
  }
  // Independent files: encode and write them side by side.
  Status results[4];
  tbb::parallel_invoke([&] { results[0] = writeVector(seq / "velodyne" / (name + ".bin"), xyzi); },
                       [&] { results[1] = writeVector(seq / "labels" / (name + ".label"), scan.labels); },
                       [&] { results[2] = io::writePng(seq / "image_2" / (name + ".png"), images.rgb); },
                       [&] { results[3] = writeFrameTruth(sim, out, frame, images); });
  for (const Status& s : results) {
    if (!s.isOk()) return s;
  }
  if (report != nullptr) {
    report->points_per_frame.push_back(scan.points_L.size());
    report->lidar_ms.push_back(lidar_ms);
    report->camera_ms.push_back(camera_ms);
    report->write_ms.push_back(watch.elapsedMs());
  }
  return Status::ok();
}

void describeScene(const Simulator& sim, double scene_ms, SimReport& report) {
  report.scene_ms = scene_ms;
  report.classes = countClasses(sim.scene());
  report.triangles = sim.scene().mesh.faceCount();
  for (const Mover& m : sim.movers()) ++report.movers[m.kind];
  report.street_length_m = sim.scene().length_m;
  for (int k = 1; k < sim.frames(); ++k) {
    report.path_length_m += (sim.T_S_L(k).translation() - sim.T_S_L(k - 1).translation()).norm();
  }
}

Result<SimReport> writeSequence(const SimParams& params, const fs::path& out, const ProgressFn& progress) {
  if (Status s = validate(params); !s.isOk()) return s;
  SimReport report;
  Stopwatch watch;
  const Simulator sim(params);
  describeScene(sim, watch.elapsedMs(), report);
  if (Status s = writeStatic(sim, out); !s.isOk()) return s;
  for (int k = 0; k < sim.frames(); ++k) {
    if (Status s = writeFrame(sim, out, k, &report); !s.isOk()) return s;
    if (progress) progress(k + 1, sim.frames());
  }
  return report;
}

}  // namespace artemis::sim
