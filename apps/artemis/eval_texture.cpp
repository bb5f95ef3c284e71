// artemis eval texture: held-out view synthesis (DESIGN.md, "How results are measured"). The run
// left every N-th frame's image out of texturing (artemis run --texture-holdout N); here its mesh
// is rendered at those frames' camera poses and compared with the real images: PSNR and SSIM over
// the pixels the rendering covers, and the covered fraction. The same run's vertices rendered as
// coloured point splats (what a coloured point-cloud map shows) are scored beside it.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "artemis/core/colour.hpp"
#include "artemis/core/log.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/eval/geometry.hpp"
#include "artemis/eval/texture.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/png.hpp"
#include "artemis/render/rasterizer.hpp"
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

// A rendering put into the real image's exposure and encoded as 8-bit sRGB.
struct Encoded {
  ImageU8 image;
  std::vector<std::uint8_t> covered;
};

Encoded encode(const render::Picture& picture, const ImageU8& real) {
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
  write(eval::exposureGain(real, out.image, out.covered));
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

int runTextureEval(const TextureEvalFlags& flags) {
  const fs::path run(flags.run);
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

  Tally mesh_tally, splat_tally;
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
    render::View view;
    view.camera = camera->camera;
    view.T_W_C = opened->trajectory[i] * camera->T_L_C;
    const Encoded rendered =
        encode(render::rasterize({mesh->arrays.vertices, mesh->arrays.triangles, mesh->colours}, view), camera->image);
    const Encoded splats =
        encode(render::splat(mesh->arrays.vertices, mesh->colours, flags.splat_radius_m, view), camera->image);
    const eval::TextureScore m = eval::compareTexture(camera->image, rendered.image, rendered.covered);
    const eval::TextureScore s = eval::compareTexture(camera->image, splats.image, splats.covered);
    mesh_tally.add(m);
    splat_tally.add(s);
    views.push_back({{"frame", frame->index},
                     {"mesh", {{"psnr_db", m.psnr_db}, {"ssim", m.ssim}, {"covered", m.covered}}},
                     {"splats", {{"psnr_db", s.psnr_db}, {"ssim", s.ssim}, {"covered", s.covered}}}});
    if (!flags.pictures.empty()) {
      const fs::path dir(flags.pictures);
      for (const auto& [name, image] : {std::pair{"mesh", &rendered.image}, std::pair{"splats", &splats.image},
                                        std::pair{"real", &camera->image}}) {
        if (Status st = io::writePng(dir / fmt::format("{:06d}_{}.png", frame->index, name), *image); !st.isOk()) {
          log::warn("{}", st.message());
        }
      }
    }
    progress.update(i + 1, d.size());
  }
  progress.finish();
  if (mesh_tally.views == 0)
    return fail(notFound(fmt::format("{}: no held-out view could be rendered", d.root().string())));
  const Json mj = mesh_tally.json();
  const Json sj = splat_tally.json();
  fmt::print("{} held-out views (every {}th frame) of {}\n", mesh_tally.views, holdout, d.root().string());
  fmt::print("{:<28} {:>10} {:>8} {:>9}\n", "", "PSNR (dB)", "SSIM", "covered");
  const auto row = [](const char* name, const Json& j) {
    fmt::print("{:<28} {:>10.2f} {:>8.4f} {:>8.1f}%\n", name, j["psnr_db"].is_null() ? 0.0 : j["psnr_db"].get<double>(),
               j["ssim"].is_null() ? 0.0 : j["ssim"].get<double>(), 100.0 * j["covered"].get<double>());
  };
  row("textured mesh", mj);
  row(fmt::format("point splats ({:.2f} m)", flags.splat_radius_m).c_str(), sj);
  if (!flags.json.empty()) {
    Json j{{"run", flags.run},
           {"holdout", holdout},
           {"mesh", mj},
           {"splats", sj},
           {"splat_radius_m", flags.splat_radius_m},
           {"views", views}};
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
  cmd->callback([flags, &exit_code] { exit_code = runTextureEval(*flags); });
}

}  // namespace artemis::cli
