// artemis eval texture: held-out view synthesis (DESIGN.md, "How results are measured"). The run
// left every N-th frame's image out of texturing (artemis run --texture-holdout N); here its mesh
// is rendered at those frames' camera poses and compared with the real images: PSNR and SSIM over
// the pixels the rendering covers, and the covered fraction. The same run's vertices rendered as
// coloured point splats (what a coloured point-cloud map shows) are scored beside it.
//
// A map of what stays holds no car that drove through the recording, but the held-out image does:
// with --boxes, the pixels inside the 2-D boxes of the listed tracks (the moving cars) are also
// left out, and the same scores are given for the static scene that remains.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "artemis/core/colour.hpp"
#include "artemis/core/log.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/kitti_boxes.hpp"
#include "artemis/eval/geometry.hpp"
#include "artemis/eval/texture.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/png.hpp"
#include "artemis/render/rasterizer.hpp"
#include "box_exclusion.hpp"
#include "commands.hpp"
#include "flag_checks.hpp"
#include "progress.hpp"
#include "run_folder.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

struct TextureEvalFlags {
  std::string run;
  std::string dataset;  // empty: the run's
  int holdout = 0;      // 0: the run's
  double splat_radius_m = 0.05;
  std::string json;
  std::string pictures;  // folder for the rendered pictures (optional)
  std::string boxes;     // KITTI tracking labels: also score the static scene, without the listed tracks
  std::string tracks;    // "0,1" or "all"; required with boxes
  int box_frame_offset = 0;
  int box_padding_px = 4;
};

// The run's mesh with its vertex colours in linear RGB (what the renderer interpolates).
struct ColouredMesh {
  eval::MeshArrays arrays;
  std::vector<Eigen::Vector3f> colours;
};

Result<ColouredMesh> readColouredMesh(const fs::path& path) {
  auto arrays = eval::readMeshArrays(path);
  if (!arrays) return arrays.status();
  if (arrays->triangles.empty()) return parseError(fmt::format("{}: no faces", path.string()));
  if (arrays->colours.empty()) {
    return parseError(fmt::format("{}: has no vertex colours: run with a camera and --texture on", path.string()));
  }
  ColouredMesh mesh{std::move(*arrays), {}};
  mesh.colours.reserve(mesh.arrays.colours.size());
  for (const auto& c : mesh.arrays.colours) {
    mesh.colours.emplace_back(static_cast<float>(srgbDecode(c[0] / 255.0)),
                              static_cast<float>(srgbDecode(c[1] / 255.0)),
                              static_cast<float>(srgbDecode(c[2] / 255.0)));
  }
  return mesh;
}

// The covered pixels that `left_out` does not mark.
std::vector<std::uint8_t> keptPixels(const std::vector<std::uint8_t>& covered,
                                     const std::vector<std::uint8_t>& left_out) {
  std::vector<std::uint8_t> kept(covered.size(), 0);
  for (std::size_t k = 0; k < kept.size(); ++k) kept[k] = covered[k] != 0 && left_out[k] == 0 ? 1 : 0;
  return kept;
}

// A rendering put into the real image's exposure and encoded as 8-bit sRGB.
struct Encoded {
  ImageU8 image;
  std::vector<std::uint8_t> covered;
};

// The exposure gain is fitted over the covered pixels that `left_out` (when given) does not mark.
Encoded encode(const render::Picture& picture, const ImageU8& real,
               const std::vector<std::uint8_t>* left_out = nullptr) {
  Encoded out{ImageU8(real.width(), real.height(), 3, 0), std::vector<std::uint8_t>(picture.face.size(), 0)};
  const auto write = [&](double gain) {
    for (int v = 0; v < real.height(); ++v) {
      for (int u = 0; u < real.width(); ++u) {
        if (picture.faceAt(u, v) == render::kNoFace) continue;
        out.covered[static_cast<std::size_t>(v) * static_cast<std::size_t>(real.width()) +
                    static_cast<std::size_t>(u)] = 1;
        for (int c = 0; c < 3; ++c) {
          const double s = srgbEncode(gain * static_cast<double>(picture.colour.at(u, v, c)));
          out.image.at(u, v, c) = static_cast<std::uint8_t>(std::lround(255.0 * s));
        }
      }
    }
  };
  write(1.0);
  if (left_out == nullptr) {
    write(eval::exposureGain(real, out.image, out.covered));
    return out;
  }
  const std::vector<std::uint8_t> kept = keptPixels(out.covered, *left_out);
  write(eval::exposureGain(real, out.image, kept));
  out.covered = kept;
  return out;
}

struct Tally {
  double squared_error = 0.0;  // summed over covered pixels and channels
  double ssim_sum = 0.0;       // ssim * pixels
  double covered_sum = 0.0;
  std::size_t pixels = 0;
  std::size_t views = 0;
  void add(const eval::TextureScore& s) {
    if (s.pixels == 0) return;
    squared_error += 3.0 * static_cast<double>(s.pixels) * 255.0 * 255.0 / std::pow(10.0, s.psnr_db / 10.0);
    ssim_sum += s.ssim * static_cast<double>(s.pixels);
    covered_sum += s.covered;
    pixels += s.pixels;
    ++views;
  }
  [[nodiscard]] Json json() const {
    if (pixels == 0) return {{"psnr_db", nullptr}, {"ssim", nullptr}, {"covered", 0.0}, {"views", views}};
    const double mse = squared_error / (3.0 * static_cast<double>(pixels));
    return {{"psnr_db", 10.0 * std::log10(255.0 * 255.0 / mse)},
            {"ssim", ssim_sum / static_cast<double>(pixels)},
            {"covered", covered_sum / static_cast<double>(views)},
            {"views", views}};
  }
};

// The labelled moving objects a static score leaves out (--boxes, --tracks).
struct MovingBoxes {
  datasets::KittiBoxLabels labels;
  std::set<int> tracks;
  int frame_offset = 0;
  int padding_px = 4;
  // The pixels of recording frame `frame`'s picture inside the tracks' boxes.
  [[nodiscard]] std::vector<std::uint8_t> leftOut(std::size_t frame, int width, int height) const {
    const long long label_frame = static_cast<long long>(frame) - frame_offset;
    if (label_frame < 0) return std::vector<std::uint8_t>(static_cast<std::size_t>(width * height), 0);
    return pixelsInBoxes(labels, tracks, static_cast<std::size_t>(label_frame), width, height, padding_px);
  }
};

Result<std::optional<MovingBoxes>> readMovingBoxes(const TextureEvalFlags& flags) {
  if (flags.boxes.empty()) return std::optional<MovingBoxes>{};
  auto labels = datasets::readKittiBoxes(flags.boxes);
  if (!labels) return labels.status();
  if (!labels->has_tracks) {
    return invalidArgument(
        fmt::format("{}: object labels have no tracks; --boxes needs KITTI tracking labels "
                    "(label_02)",
                    flags.boxes));
  }
  auto tracks = parseTrackList(flags.tracks, *labels);
  if (!tracks) return Status(tracks.status().code(), "--tracks: " + tracks.status().message());
  for (const int id : *tracks) {
    const bool labelled = std::any_of(labels->boxes.begin(), labels->boxes.end(),
                                      [id](const datasets::KittiBox& b) { return b.track_id == id; });
    if (!labelled) return invalidArgument(fmt::format("--tracks: {} has no track {}", flags.boxes, id));
  }
  return std::optional<MovingBoxes>(
      MovingBoxes{std::move(*labels), std::move(*tracks), flags.box_frame_offset, flags.box_padding_px});
}

// Scores of the mesh and the splats, over every covered pixel and over the static scene.
struct Tallies {
  Tally mesh, splats, static_mesh, static_splats;
  double left_out = 0.0;  // covered mesh pixels inside the moving boxes, summed
  double covered = 0.0;   // covered mesh pixels, summed
};

// Renders the run's mesh and splats at one held-out view and scores them against its image; writes
// the pictures into `pictures` when it is not empty. Returns the view's JSON row.
Json scoreView(const ColouredMesh& mesh, const CameraView& camera, const Isometry3d& T_W_L, std::size_t frame,
               const TextureEvalFlags& flags, const std::optional<MovingBoxes>& moving, Tallies& tallies) {
  render::View view;
  view.camera = camera.camera;
  view.T_W_C = T_W_L * camera.T_L_C;
  const render::Picture mesh_picture =
      render::rasterize({mesh.arrays.vertices, mesh.arrays.triangles, mesh.colours}, view);
  const render::Picture splat_picture = render::splat(mesh.arrays.vertices, mesh.colours, flags.splat_radius_m, view);
  const Encoded rendered = encode(mesh_picture, camera.image);
  const Encoded splats = encode(splat_picture, camera.image);
  const eval::TextureScore m = eval::compareTexture(camera.image, rendered.image, rendered.covered);
  const eval::TextureScore s = eval::compareTexture(camera.image, splats.image, splats.covered);
  tallies.mesh.add(m);
  tallies.splats.add(s);
  const auto score = [](const eval::TextureScore& t) {
    return Json{{"psnr_db", t.psnr_db}, {"ssim", t.ssim}, {"covered", t.covered}};
  };
  Json row{{"frame", frame}, {"mesh", score(m)}, {"splats", score(s)}};
  if (moving) {
    const std::vector<std::uint8_t> left_out = moving->leftOut(frame, camera.image.width(), camera.image.height());
    const Encoded rendered_static = encode(mesh_picture, camera.image, &left_out);
    const Encoded splats_static = encode(splat_picture, camera.image, &left_out);
    const eval::TextureScore ms = eval::compareTexture(camera.image, rendered_static.image, rendered_static.covered);
    const eval::TextureScore ss = eval::compareTexture(camera.image, splats_static.image, splats_static.covered);
    tallies.static_mesh.add(ms);
    tallies.static_splats.add(ss);
    tallies.covered += static_cast<double>(m.pixels);
    tallies.left_out += static_cast<double>(m.pixels - ms.pixels);
    row["static"] = {{"mesh", score(ms)}, {"splats", score(ss)}};
  }
  if (!flags.pictures.empty()) {
    const fs::path dir(flags.pictures);
    for (const auto& [name, image] :
         {std::pair{"mesh", &rendered.image}, std::pair{"splats", &splats.image}, std::pair{"real", &camera.image}}) {
      if (Status st = io::writePng(dir / fmt::format("{:06d}_{}.png", frame, name), *image); !st.isOk()) {
        log::warn("{}", st.message());
      }
    }
  }
  return row;
}

void printRow(const std::string& name, const Json& j) {
  fmt::print("{:<34} {:>10.2f} {:>8.4f} {:>8.1f}%\n", name, j["psnr_db"].is_null() ? 0.0 : j["psnr_db"].get<double>(),
             j["ssim"].is_null() ? 0.0 : j["ssim"].get<double>(), 100.0 * j["covered"].get<double>());
}

// Prints the table and returns the scores' JSON (the static part with --boxes).
Json report(const Tallies& tallies, const TextureEvalFlags& flags, const std::optional<MovingBoxes>& moving) {
  Json j{{"mesh", tallies.mesh.json()}, {"splats", tallies.splats.json()}};
  fmt::print("{:<34} {:>10} {:>8} {:>9}\n", "", "PSNR (dB)", "SSIM", "covered");
  printRow("textured mesh", j["mesh"]);
  printRow(fmt::format("point splats ({:.2f} m)", flags.splat_radius_m), j["splats"]);
  if (moving) {
    const double share = tallies.covered > 0.0 ? tallies.left_out / tallies.covered : 0.0;
    j["static"] = {{"tracks", moving->tracks},
                   {"boxes", flags.boxes},
                   {"box_frame_offset", moving->frame_offset},
                   {"box_padding_px", moving->padding_px},
                   {"left_out", share},
                   {"mesh", tallies.static_mesh.json()},
                   {"splats", tallies.static_splats.json()}};
    printRow("textured mesh, static scene", j["static"]["mesh"]);
    printRow(fmt::format("point splats ({:.2f} m), static scene", flags.splat_radius_m), j["static"]["splats"]);
    fmt::print("static scene: the 2-D boxes of tracks {} ({}) left out: {:.1f}% of the mesh's covered pixels\n",
               fmt::join(moving->tracks, ","), flags.boxes, 100.0 * share);
  }
  return j;
}

int runTextureEval(const TextureEvalFlags& flags) {
  const fs::path run(flags.run);
  auto moving = readMovingBoxes(flags);
  if (!moving) return fail(moving.status());
  datasets::DatasetOptions options;
  options.load_images = true;
  auto opened = openRunDataset(run, flags.dataset, options);
  if (!opened) return fail(opened.status());
  const int holdout = flags.holdout > 0 ? flags.holdout : opened->recording.texture_holdout;
  if (holdout <= 0) {
    return fail(invalidArgument(fmt::format(
        "{}: the run held no image out of texturing; run with --texture-holdout 5 (or give --holdout)", flags.run)));
  }
  auto mesh = readColouredMesh(run / "mesh.ply");
  if (!mesh) return fail(mesh.status());
  const datasets::Dataset& d = *opened->dataset;
  if (!flags.pictures.empty()) fs::create_directories(flags.pictures);

  Tallies tallies;
  Json views = Json::array();
  ProgressLine progress("rendering", "views");
  for (std::size_t i = 0; i < d.size(); ++i) {
    if ((i + 1) % static_cast<std::size_t>(holdout) != 0) continue;
    auto frame = d.frame(i);
    if (!frame) {
      log::warn("frame {} skipped: {}", d.firstIndex() + i, frame.status().message());
      continue;
    }
    const CameraView* camera = frame->cameras.empty() ? nullptr : &frame->cameras.front();
    if (camera == nullptr || !camera->hasImage() || camera->image.channels() != 3) {
      log::warn("frame {} skipped: no colour image", frame->index);
      continue;
    }
    views.push_back(scoreView(*mesh, *camera, opened->trajectory[i], frame->index, flags, *moving, tallies));
    progress.update(i + 1, d.size());
  }
  progress.finish();
  if (tallies.mesh.views == 0)
    return fail(notFound(fmt::format("{}: no held-out view could be rendered", d.root().string())));
  fmt::print("{} held-out views (every {}th frame) of {}\n", tallies.mesh.views, holdout, d.root().string());
  Json j = report(tallies, flags, *moving);
  if (!flags.json.empty()) {
    j["run"] = flags.run;
    j["holdout"] = holdout;
    j["splat_radius_m"] = flags.splat_radius_m;
    j["views"] = std::move(views);
    const std::string text = j.dump(2) + "\n";
    if (Status st = io::writeFileAtomic(flags.json, std::as_bytes(std::span(text.data(), text.size()))); !st.isOk()) {
      return fail(st);
    }
  }
  return 0;
}

}  // namespace

void addEvalTextureCommand(CLI::App& eval, int& exit_code) {
  auto flags = std::make_shared<TextureEvalFlags>();
  auto* cmd = eval.add_subcommand(
      "texture",
      "Held-out texture fidelity: the run's mesh rendered at the frames it left out of texturing (artemis run "
      "--texture-holdout N) against their real images: PSNR and SSIM over the covered pixels (after matching the "
      "view's exposure with one gain), and the covered fraction; beside it the run's vertices as coloured point "
      "splats, what a coloured point-cloud map shows");
  cmd->add_option("RUN", flags->run, "Run folder: mesh.ply with colours, trajectory.txt, config.json")->required();
  cmd->add_option("--dataset", flags->dataset, "The recording (default: the run's)");
  cmd->add_option("--holdout", flags->holdout, "Every N-th frame was held out (default: the run's setting)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--splat-radius", flags->splat_radius_m, "Radius of the point splats (m)")
      ->capture_default_str()
      ->check(within(1e-4, 10.0));
  cmd->add_option("--pictures", flags->pictures, "Also write the rendered and real pictures into this folder");
  cmd->add_option("--json", flags->json, "Also write the scores (and per view) to this JSON file");
  auto* boxes = cmd->add_option("--boxes", flags->boxes,
                                "KITTI tracking labels (label_02): also score the static scene, leaving out the "
                                "pixels inside the 2-D boxes of --tracks (the cars that drive through the recording, "
                                "which a map of what stays does not hold)");
  auto* tracks = cmd->add_option("--tracks", flags->tracks,
                                 "--boxes: the track ids to leave out, comma-separated (0,1), or 'all'; required "
                                 "with --boxes");
  boxes->needs(tracks);
  tracks->needs(boxes);
  cmd->add_option("--box-frame-offset", flags->box_frame_offset,
                  "--boxes: the boxes of label frame f belong to recording frame f + K")
      ->capture_default_str()
      ->check(CLI::Range(-100000, 100000));
  cmd->add_option("--box-padding", flags->box_padding_px, "--boxes: grow each 2-D box by this many pixels a side")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  cmd->callback([flags, &exit_code] { exit_code = runTextureEval(*flags); });
}

}  // namespace artemis::cli
