// classBoundaryFaces and readFaceClasses (geometry.hpp): which faces of a mesh join two classes of
// a labelled reference surface.

#include <fmt/format.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <limits>

#include "artemis/eval/geometry.hpp"
#include "artemis/io/ply.hpp"
#include "cloud_kdtree.hpp"
#include "surface_sampling.hpp"

namespace artemis::eval {

Result<ClassBoundaryFaces> classBoundaryFaces(const MeshArrays& mesh, const MeshArrays& reference,
                                              const std::vector<std::uint16_t>& reference_face_classes,
                                              std::uint16_t a, std::uint16_t b, double max_distance_m) {
  if (reference_face_classes.size() != reference.triangles.size()) {
    return invalidArgument(fmt::format("{} face classes for {} reference faces", reference_face_classes.size(),
                                       reference.triangles.size()));
  }
  if (const std::string bad = detail::checkTriangleIndices(mesh); !bad.empty()) return invalidArgument(bad);
  std::vector<std::uint32_t> sample_faces;
  std::vector<Eigen::Vector3f> samples;
  try {
    samples = detail::sampleSurface(reference, 400.0, 0, 1, {}, nullptr, &sample_faces);
  } catch (const std::invalid_argument& e) {
    return invalidArgument(std::string("reference: ") + e.what());
  }
  if (samples.empty()) return invalidArgument("the reference mesh has no face with area");
  detail::CloudAdaptor adaptor{&samples};
  detail::CloudKdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();

  constexpr std::uint16_t kUnknown = std::numeric_limits<std::uint16_t>::max();
  std::vector<std::uint16_t> vertex_class(mesh.vertices.size(), kUnknown);
  const auto reach = static_cast<float>(max_distance_m * max_distance_m);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.vertices.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (!mesh.vertices[i].allFinite()) continue;
      std::uint32_t nearest = 0;
      float distance = 0.0f;
      if (tree.knnSearch(mesh.vertices[i].data(), 1, &nearest, &distance) == 1 && distance <= reach) {
        vertex_class[i] = reference_face_classes[sample_faces[nearest]];
      }
    }
  });

  ClassBoundaryFaces out;
  out.a = a;
  out.b = b;
  out.faces = mesh.triangles.size();
  for (const std::uint16_t c : vertex_class) out.unlabelled_vertices += c == kUnknown ? 1 : 0;
  for (const auto& t : mesh.triangles) {
    bool has_a = false;
    bool has_b = false;
    for (const std::uint32_t v : t) {
      has_a = has_a || vertex_class[v] == a;
      has_b = has_b || vertex_class[v] == b;
    }
    out.faces_with_a += has_a ? 1 : 0;
    out.joining += has_a && has_b ? 1 : 0;
  }
  out.share = out.faces_with_a > 0 ? static_cast<double>(out.joining) / static_cast<double>(out.faces_with_a) : 0.0;
  return out;
}

Result<std::vector<std::uint16_t>> readFaceClasses(const std::filesystem::path& path) {
  auto ply = io::readPly(path);
  if (!ply) return ply.status();
  const io::PlyElement* face = ply->find("face");
  if (face == nullptr || face->find("class_id") == nullptr) return std::vector<std::uint16_t>{};
  auto classes = ply->scalarAs<std::uint16_t>("face", "class_id");
  if (!classes) return Status(classes.status().code(), path.string() + ": " + classes.status().message());
  return std::move(*classes);
}

}  // namespace artemis::eval
