#include "run_mesh.hpp"

#include <fmt/format.h>

#include "artemis/eval/geometry.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/pipeline/output_folder.hpp"
#include "run_folder.hpp"

namespace artemis::cli {

namespace fs = std::filesystem;

Result<RunMesh> readRunMesh(const fs::path& path) {
  std::error_code ec;
  const bool folder = fs::is_directory(path, ec);
  if (folder) {
    if (Status s = pipeline::settleOutputFolder(path); !s.isOk()) return s;
  }
  const fs::path mesh_path = folder ? path / "mesh.ply" : path;
  auto arrays = eval::readMeshArrays(mesh_path);
  if (!arrays) return arrays.status();
  if (arrays->triangles.empty()) return parseError(fmt::format("{}: has no faces", mesh_path.string()));
  RunMesh mesh;
  mesh.positions = std::move(arrays->vertices);
  mesh.triangles = std::move(arrays->triangles);
  mesh.rgb = std::move(arrays->colours);
  auto ply = io::readPly(mesh_path);  // the semantic properties (readMeshArrays keeps geometry and colour)
  if (!ply) return ply.status();
  const io::PlyElement* vertex = ply->find("vertex");
  if (vertex != nullptr && vertex->find("class_id") != nullptr) {
    auto classes = ply->scalarAs<int>("vertex", "class_id");
    if (!classes) return classes.status();
    mesh.class_id.reserve(classes->size());
    for (std::size_t i = 0; i < classes->size(); ++i) {
      const int c = (*classes)[i];
      if (c < 0 || c > semantics::kMaxClasses) {
        return parseError(fmt::format("{}: vertex {} has class_id {}, outside 0..{}", mesh_path.string(), i, c,
                                      semantics::kMaxClasses));
      }
      mesh.class_id.push_back(static_cast<std::uint8_t>(c));
    }
    if (vertex->find("confidence") != nullptr) {
      auto confidence = ply->scalarAs<float>("vertex", "confidence");
      if (!confidence) return confidence.status();
      mesh.confidence = std::move(*confidence);
    }
  }
  const fs::path semantics_json = (folder ? path : path.parent_path()) / "semantics.json";
  if (!mesh.class_id.empty() && fs::exists(semantics_json, ec)) {
    auto j = readJsonFile(semantics_json, "");
    if (!j) return j.status();
    const std::string file = semantics_json.string();
    if (j->contains("vocabulary")) {
      auto vocabulary = semantics::Vocabulary::parse((*j)["vocabulary"].dump(), file);
      if (!vocabulary) return vocabulary.status();
      mesh.vocabulary = std::move(*vocabulary);
    }
    if (j->contains("prompted") && (*j)["prompted"].is_array()) {
      for (const auto& id : (*j)["prompted"]) {
        const bool valid = id.is_number_integer() && id.get<long long>() > 0 &&
                           id.get<long long>() <= semantics::kMaxClasses &&
                           mesh.vocabulary.find(static_cast<semantics::ClassId>(id.get<int>())) != nullptr;
        if (!valid) {
          return parseError(fmt::format("{}: prompted class {} is not in the vocabulary", file, id.dump()));
        }
        mesh.prompted.push_back(static_cast<semantics::ClassId>(id.get<int>()));
      }
    }
  }
  return mesh;
}

}  // namespace artemis::cli
