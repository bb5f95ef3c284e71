// artemis render RUN --query "car" (--pose N | --camera ...) -o out.png [--highlight-mask mask.png]:
// a headless picture (CPU only) of the run's mesh, textured when the run was, with the surfaces of
// the queried classes highlighted (semantic rendering, paper §III-C). The camera is a dataset
// camera at a frame's pose (the run's trajectory, the recording's camera model), or a free camera
// looking from one point at another.
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/io/png.hpp"
#include "artemis/render/highlight.hpp"
#include "artemis/render/rasterizer.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "commands.hpp"
#include "flag_checks.hpp"
#include "run_folder.hpp"
#include "run_mesh.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;

struct RenderFlags {
  std::string run;
  std::string query;
  long long pose = -1;
  std::string camera;  // "ex,ey,ez,tx,ty,tz"
  int width = 1242;
  int height = 375;
  double fov_deg = 80.0;
  std::string dataset;
  std::string output;
  std::string mask;
  std::string depth;
  bool json = false;
};

// A free camera at `eye` looking at `target`, world z up (x right, y down, z forward).
Result<render::View> freeView(const RenderFlags& flags) {
  std::vector<double> v;
  std::stringstream ss(flags.camera);
  for (std::string item; std::getline(ss, item, ',');) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size() || !std::isfinite(v.back())) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      return invalidArgument(fmt::format("--camera: '{}' is not a number (want ex,ey,ez,tx,ty,tz)", item));
    }
  }
  if (v.size() != 6) return invalidArgument(fmt::format("--camera: {} numbers, want 6: ex,ey,ez,tx,ty,tz", v.size()));
  if (flags.width <= 0 || flags.height <= 0 || flags.width > 16384 || flags.height > 16384) {
    return invalidArgument(fmt::format("--width/--height {}x{}: want 1..16384 pixels", flags.width, flags.height));
  }
  if (!(flags.fov_deg > 1.0 && flags.fov_deg < 179.0)) {
    return invalidArgument(fmt::format("--fov {}: want a horizontal field of view in (1, 179) degrees", flags.fov_deg));
  }
  const Eigen::Vector3d eye(v[0], v[1], v[2]);
  const Eigen::Vector3d target(v[3], v[4], v[5]);
  const Eigen::Vector3d forward = target - eye;
  if (forward.norm() < 1e-9) return invalidArgument("--camera: the eye and the target are the same point");
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d up(0, 0, 1);
  if (std::abs(z.dot(up)) > 0.999) up = Eigen::Vector3d(0, 1, 0);  // looking straight up or down
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  render::View view;
  view.camera.width_px = flags.width;
  view.camera.height_px = flags.height;
  view.camera.fx_px = view.camera.fy_px = 0.5 * flags.width / std::tan(0.5 * flags.fov_deg * M_PI / 180.0);
  view.camera.cx_px = 0.5 * (flags.width - 1);
  view.camera.cy_px = 0.5 * (flags.height - 1);
  Eigen::Matrix3d R;
  R << x, y, z;
  view.T_W_C.linear() = R;
  view.T_W_C.translation() = eye;
  return view;
}

// The recording's camera at frame `pose` of the run (its trajectory and the camera model of the
// recording in config.json, or --dataset).
Result<render::View> datasetView(const RenderFlags& flags) {
  datasets::DatasetOptions options;
  options.load_images = false;
  auto opened = openRunDataset(flags.run, flags.dataset, options);
  if (!opened) return opened.status();
  const datasets::Dataset& d = *opened->dataset;
  const auto first = static_cast<long long>(d.firstIndex());
  if (flags.pose < first || flags.pose >= first + static_cast<long long>(d.size())) {
    return invalidArgument(fmt::format("--pose {}: the run mapped frames {}..{} of {}", flags.pose, first,
                                       first + static_cast<long long>(d.size()) - 1, d.root().string()));
  }
  const auto i = static_cast<std::size_t>(flags.pose - first);
  auto frame = d.frame(i);
  if (!frame) return frame.status();
  if (frame->cameras.empty()) return notFound(fmt::format("{}: frame {} has no camera", d.root().string(), flags.pose));
  render::View view;
  view.camera = frame->cameras.front().camera;
  view.T_W_C = opened->trajectory[i] * frame->cameras.front().T_L_C;
  return view;
}

int runRender(const RenderFlags& flags) {
  const bool free_camera = !flags.camera.empty();
  if (free_camera == (flags.pose >= 0))
    return fail(invalidArgument("give either --pose N or --camera ex,ey,ez,tx,ty,tz"));
  auto mesh = readRunMesh(flags.run);
  if (!mesh) return fail(mesh.status());
  auto view = free_camera ? freeView(flags) : datasetView(flags);
  if (!view) return fail(view.status());

  nlohmann::json report = {
      {"output", flags.output}, {"width", view->camera.width_px}, {"height", view->camera.height_px}};
  std::vector<std::uint8_t> classes;  // highlighted, in the query's order
  if (!flags.query.empty()) {
    if (mesh->class_id.empty()) {
      return fail(invalidArgument(fmt::format(
          "{}: the mesh has no classes to highlight; run with --query (and a segmenter) first", flags.run)));
    }
    auto grounder = semantics::QueryGrounder::create(mesh->vocabulary);
    if (!grounder) return fail(grounder.status());
    auto grounding = grounder->ground(flags.query);
    if (!grounding) return fail(grounding.status());
    nlohmann::json matched = nlohmann::json::array();
    for (const semantics::ClassId c : grounding->classes) {
      const bool prompted = std::find(mesh->prompted.begin(), mesh->prompted.end(), c) != mesh->prompted.end();
      const std::string name(mesh->vocabulary.name(c));
      if (!prompted && !mesh->prompted.empty()) {
        log::warn("'{}' was not among the classes this run looked for: none of its surfaces is labelled", name);
      }
      const render::Rgb8 colour = render::highlightColour(classes.size());
      classes.push_back(c);
      matched.push_back({{"id", c}, {"name", name}, {"rgb", colour}});
    }
    report["query"] = flags.query;
    report["matched"] = matched;
    if (classes.empty()) {
      const std::string why = semantics::describe(*grounding, grounder->vocabulary());
      log::warn("{}", why.substr(0, why.find('\n')));
    }
  }

  Stopwatch clock;
  std::vector<Eigen::Vector3f> colours;
  if (!mesh->rgb.empty()) {
    colours.reserve(mesh->rgb.size());
    for (const auto& c : mesh->rgb) colours.emplace_back(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f);
  }
  const render::MeshArrays arrays{mesh->positions, mesh->triangles, colours};
  const render::Picture picture = render::rasterize(arrays, *view);
  std::vector<std::uint8_t> highlight;
  if (!classes.empty()) highlight = render::vertexHighlight(mesh->class_id, classes);
  const render::ShadedPicture shaded = render::shade(arrays, picture, *view, highlight);
  const double ms = clock.elapsedMs();
  if (Status s = io::writePng(flags.output, shaded.image); !s.isOk()) return fail(s);
  if (!flags.mask.empty()) {
    if (Status s = io::writePng(flags.mask, shaded.mask); !s.isOk()) return fail(s);
    report["highlight_mask"] = flags.mask;
  }
  if (!flags.depth.empty()) {
    // As the simulator's gt/depth_2: z along the optical axis in mm, 0 where no surface (or beyond 65.5 m).
    ImageU16 depth(picture.depth.width(), picture.depth.height(), 1, 0);
    for (int v = 0; v < depth.height(); ++v) {
      for (int u = 0; u < depth.width(); ++u) {
        const double z_mm = 1000.0 * static_cast<double>(picture.depth.at(u, v));
        if (std::isfinite(z_mm) && z_mm < 65535.0) depth.at(u, v) = static_cast<std::uint16_t>(std::lround(z_mm));
      }
    }
    if (Status s = io::writePng(flags.depth, depth); !s.isOk()) return fail(s);
    report["depth"] = flags.depth;
  }
  report["covered_pixels"] = shaded.covered_pixels;
  report["highlighted_pixels"] = shaded.highlighted_pixels;
  report["ms"] = ms;
  if (flags.json) {
    fmt::print("{}\n", report.dump(2));
  } else {
    std::string matched;
    for (const auto& m : report.value("matched", nlohmann::json::array())) {
      matched += (matched.empty() ? "" : ", ") + m["name"].get<std::string>();
    }
    fmt::print("{}: {}x{}, {} pixels show the mesh, {} highlighted{} ({:.0f} ms)\n", flags.output,
               view->camera.width_px, view->camera.height_px, shaded.covered_pixels, shaded.highlighted_pixels,
               flags.query.empty() ? "" : fmt::format(" ({})", matched.empty() ? "no class matched" : matched), ms);
  }
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<RenderFlags>();
  auto* cmd = app.add_subcommand(
      "render",
      "A picture of a run's mesh (CPU, headless): textured when the run was, with the surfaces of the classes a "
      "query names highlighted, from a dataset camera at a frame's pose or from a free camera.");
  cmd->add_option("RUN", flags->run,
                  "Run folder of artemis run (mesh.ply, semantics.json, trajectory.txt, "
                  "config.json), or a mesh PLY (with --camera)")
      ->required();
  cmd->add_option("--query,-q", flags->query, "Highlight the classes this names, e.g. \"cars and people\"");
  cmd->add_option("--pose", flags->pose, "Frame number of the recording: its camera (model and pose) takes the picture")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--camera", flags->camera, "Free camera: eye and target in world coordinates, ex,ey,ez,tx,ty,tz");
  cmd->add_option("--width", flags->width, "Free camera: picture width in pixels")
      ->capture_default_str()
      ->check(within(1, 16384));
  cmd->add_option("--height", flags->height, "Free camera: picture height in pixels")
      ->capture_default_str()
      ->check(within(1, 16384));
  cmd->add_option("--fov", flags->fov_deg, "Free camera: horizontal field of view in degrees")
      ->capture_default_str()
      ->check(within(1.0, 179.0));
  cmd->add_option("--dataset", flags->dataset, "The recording, where it is no longer where config.json says");
  cmd->add_option("-o,--output", flags->output, "PNG to write")->required();
  cmd->add_option("--highlight-mask", flags->mask,
                  "Also write an 8-bit PNG: 255 where a highlighted surface is the visible one, else 0");
  cmd->add_option("--depth", flags->depth,
                  "Also write a 16-bit PNG of the mesh's depth along the optical axis in mm (0: no surface)");
  cmd->add_flag("--json", flags->json, "Print the result as JSON");
  cmd->callback([flags, &exit_code] { exit_code = runRender(*flags); });
}

}  // namespace artemis::cli
