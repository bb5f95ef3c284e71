#include "run_classes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/ply.hpp"
#include "run_folder.hpp"
#include "segmenter_setup.hpp"

namespace artemis::cli {

namespace fs = std::filesystem;

Result<RunClasses> readRunClasses(const fs::path& path) {
  auto j = readJsonFile(path, "; the run has no semantics (make it with artemis run --query)");
  if (!j) return j.status();
  const std::string file = path.string();
  if (!j->is_object() || !j->contains("vocabulary") || !(*j)["vocabulary"].is_object()) {
    return parseError(file + ": no \"vocabulary\" object");
  }
  auto vocabulary = semantics::Vocabulary::parse((*j)["vocabulary"].dump(), file);
  if (!vocabulary) return vocabulary.status();
  if (!j->contains("prompted") || !(*j)["prompted"].is_array()) return parseError(file + ": no \"prompted\" array");
  RunClasses out{std::move(*vocabulary), {}};
  for (const auto& id_json : (*j)["prompted"]) {
    if (!id_json.is_number_integer())
      return parseError(fmt::format("{}: prompted id {} is not an integer", file, id_json.dump()));
    const auto id = id_json.get<long long>();
    const semantics::SemanticClass* cls =
        id > 0 && id <= semantics::kMaxClasses ? out.vocabulary.find(static_cast<semantics::ClassId>(id)) : nullptr;
    if (cls == nullptr) return parseError(fmt::format("{}: prompted class {} is not in the vocabulary", file, id));
    const bool seen = std::any_of(out.evaluated.begin(), out.evaluated.end(),
                                  [&](const eval::EvaluatedClass& c) { return c.id == cls->id; });
    if (!seen) out.evaluated.push_back({cls->id, cls->name});
  }
  if (out.evaluated.empty()) return parseError(file + ": no prompted class, nothing to score");
  return out;
}

Result<MeshClasses> readMeshClasses(const fs::path& path) {
  const std::string file = path.string();
  auto ply = io::readPly(path);
  if (!ply) return ply.status();
  if (ply->find("vertex") == nullptr) return parseError(file + ": no 'vertex' element");
  const io::PlyProperty* class_id = ply->find("vertex")->find("class_id");
  if (class_id == nullptr || class_id->is_list) {
    return parseError(file + ": has no class_id: run with --query (a mesh without semantics cannot be scored)");
  }
  std::array<std::vector<float>, 3> xyz;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    auto column = ply->scalarAs<float>("vertex", std::array{"x", "y", "z"}[axis]);
    if (!column) return Status(column.status().code(), file + ": " + column.status().message());
    xyz[axis] = std::move(*column);
  }
  auto ids = ply->scalarAs<std::int32_t>("vertex", "class_id");
  if (!ids) return Status(ids.status().code(), file + ": " + ids.status().message());
  MeshClasses mesh;
  mesh.vertices.resize(xyz[0].size());
  mesh.classes.resize(xyz[0].size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const std::int32_t id = (*ids)[i];
    if (id < 0 || id > semantics::kMaxClasses) {
      return parseError(
          fmt::format("{}: vertex {} has class_id {}, expected 0..{}", file, i, id, semantics::kMaxClasses));
    }
    mesh.vertices[i] = {xyz[0][i], xyz[1][i], xyz[2][i]};
    mesh.classes[i] = static_cast<eval::SemanticId>(id);
  }
  return mesh;
}

Result<ScoredRun> readScoredRun(const fs::path& run) {
  auto classes = readRunClasses(run / "semantics.json");
  if (!classes) return classes.status();
  auto recording = readRunRecording(run / "config.json");
  if (!recording) return recording.status();
  auto trajectory = datasets::readPoseFile(run / "trajectory.txt");
  if (!trajectory) return trajectory.status();
  auto mesh = readMeshClasses(run / "mesh.ply");
  if (!mesh) return mesh.status();
  return ScoredRun{std::move(*classes), std::move(*recording), std::move(*trajectory), std::move(*mesh)};
}

Result<RunSegmenter> rebuildRunSegmenter(const fs::path& run, const RunClasses& classes, const fs::path& dataset_root) {
  const fs::path semantics_json = run / "semantics.json";
  auto text = readJsonFile(semantics_json, "");
  if (!text) return text.status();
  auto choice = segmenterChoiceFromJson(text->dump(), semantics_json.string());
  if (!choice) return choice.status();
  auto grounder = semantics::QueryGrounder::create(classes.vocabulary);
  if (!grounder) return grounder.status();
  RunSegmenter out;
  out.grounder = std::make_unique<semantics::QueryGrounder>(std::move(*grounder));
  auto segmenter = makeSegmenter(*choice, classes.vocabulary, out.grounder.get(), dataset_root, nullptr);
  if (!segmenter) return segmenter.status();
  out.segmenter = std::move(*segmenter);
  for (const auto& c : classes.evaluated) out.prompts.push_back(c.id);
  return out;
}

const CameraView* frustumCamera(const Frame& frame) {
  for (const auto& view : frame.cameras) {
    if (view.name == "image_2" || view.name == "image_02") return &view;
  }
  return frame.cameras.empty() ? nullptr : &frame.cameras.front();
}

std::vector<eval::SemanticId> classesFromMasks(const semantics::SemanticObservation& observation,
                                               const std::vector<Eigen::Vector2i>& pixel,
                                               const std::vector<std::uint8_t>& in_frustum) {
  std::vector<eval::SemanticId> out(pixel.size(), eval::kNoSemanticClass);
  for (std::size_t k = 0; k < pixel.size(); ++k) {
    if (in_frustum[k] != 0) out[k] = observation.classAt(pixel[k].x(), pixel[k].y());
  }
  return out;
}

nlohmann::ordered_json confusionJson(const eval::SemanticScore& s) {
  using Json = nlohmann::ordered_json;
  const eval::ConfusionMatrix& m = s.confusion;
  Json rows = Json::array();
  Json columns = Json::array();
  for (const auto& c : s.classes) {
    rows.push_back(c.name);
    columns.push_back(c.name);
  }
  rows.push_back("other");
  columns.push_back("none");
  columns.push_back("missed");
  Json counts = Json::array();
  for (std::size_t r = 0; r < m.rows(); ++r) {
    Json row = Json::array();
    for (std::size_t c = 0; c < m.columns(); ++c) row.push_back(m.at(r, c));
    counts.push_back(std::move(row));
  }
  return {{"rows", rows}, {"columns", columns}, {"counts", counts}};
}

std::string percent(bool defined, double fraction) {
  return defined ? fmt::format("{:.2f} %", 100.0 * fraction) : std::string("-");
}

}  // namespace artemis::cli
