// readMeshArrays: any PLY with x, y, z vertices, with or without faces.

#include <fmt/format.h>

#include <limits>
#include <string>
#include <type_traits>
#include <variant>

#include "artemis/core/log.hpp"
#include "artemis/eval/geometry.hpp"
#include "artemis/io/ply.hpp"

namespace artemis::eval {

namespace {

// Polygons (any integer list type) fanned into triangles around their first corner.
Status appendFaces(const io::PlyElement& faces, const io::PlyProperty& indices, std::size_t vertex_count,
                   const std::string& file, std::vector<std::array<std::uint32_t, 3>>& triangles) {
  if (!indices.is_list) {
    return parseError(fmt::format("{}: face property '{}' is not a list", file, indices.name));
  }
  std::size_t short_faces = 0;
  Status status = std::visit(
      [&](const auto& values) -> Status {
        using T = typename std::decay_t<decltype(values)>::value_type;
        if constexpr (!std::is_integral_v<T>) {
          return parseError(fmt::format("{}: face property '{}' holds floating-point values, not vertex indices", file,
                                        indices.name));
        } else {
          const auto index_at = [&](std::size_t face, std::size_t i, std::uint32_t& out) -> Status {
            // NOLINTNEXTLINE(bugprone-signed-char-misuse): int8 indices are numbers; a negative one is reported.
            const auto v = static_cast<long long>(values[i]);
            if (v < 0 || static_cast<unsigned long long>(v) >= vertex_count) {
              return parseError(fmt::format("{}: face {} has vertex index {}, but there are {} vertices", file, face, v,
                                            vertex_count));
            }
            out = static_cast<std::uint32_t>(v);
            return Status::ok();
          };
          for (std::size_t f = 0; f < faces.count; ++f) {
            const std::size_t begin = indices.list_offsets[f];
            const std::size_t end = indices.list_offsets[f + 1];
            if (end - begin < 3) {
              ++short_faces;
              continue;
            }
            std::array<std::uint32_t, 3> tri{};
            if (Status s = index_at(f, begin, tri[0]); !s.isOk()) return s;
            if (Status s = index_at(f, begin + 1, tri[2]); !s.isOk()) return s;
            for (std::size_t i = begin + 2; i < end; ++i) {
              tri[1] = tri[2];
              if (Status s = index_at(f, i, tri[2]); !s.isOk()) return s;
              triangles.push_back(tri);
            }
          }
          return Status::ok();
        }
      },
      indices.values);
  if (status.isOk() && short_faces > 0) {
    log::warn("{}: {} faces with fewer than 3 vertices skipped", file, short_faces);
  }
  return status;
}

// A NaN or infinite vertex would be scored, drawn or sampled as if it were a place.
Status checkFinite(const std::vector<Eigen::Vector3f>& vertices, const std::string& file) {
  std::size_t bad = 0;
  std::size_t first = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (vertices[i].allFinite()) continue;
    if (bad++ == 0) first = i;
  }
  if (bad == 0) return Status::ok();
  return parseError(fmt::format("{}: vertex {} is not finite ({} of {} vertices have NaN or infinite coordinates)",
                                file, first, bad, vertices.size()));
}

}  // namespace

Result<MeshArrays> readMeshArrays(const std::filesystem::path& path) {
  const std::string file = path.string();
  auto ply = io::readPly(path);
  if (!ply) return ply.status();

  MeshArrays mesh;
  const io::PlyElement* vertex = ply->find("vertex");
  if (vertex == nullptr) return parseError(file + ": no 'vertex' element");
  if (vertex->count > std::numeric_limits<std::uint32_t>::max()) {
    return parseError(fmt::format("{}: {} vertices, more than 2^32 - 1", file, vertex->count));
  }
  std::array<std::vector<float>, 3> xyz;
  const std::array<const char*, 3> axes = {"x", "y", "z"};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    auto column = ply->scalarAs<float>("vertex", axes[axis]);
    if (!column) return Status(column.status().code(), file + ": " + column.status().message());
    xyz[axis] = std::move(*column);
  }
  mesh.vertices.resize(vertex->count);
  for (std::size_t i = 0; i < vertex->count; ++i) mesh.vertices[i] = {xyz[0][i], xyz[1][i], xyz[2][i]};
  if (Status s = checkFinite(mesh.vertices, file); !s.isOk()) return s;
  if (vertex->find("red") != nullptr && vertex->find("green") != nullptr && vertex->find("blue") != nullptr) {
    std::array<std::vector<std::uint8_t>, 3> rgb;
    const std::array<const char*, 3> channels = {"red", "green", "blue"};
    for (std::size_t c = 0; c < 3; ++c) {
      auto column = ply->scalarAs<std::uint8_t>("vertex", channels[c]);
      if (!column) return Status(column.status().code(), file + ": " + column.status().message());
      rgb[c] = std::move(*column);
    }
    mesh.colours.resize(vertex->count);
    for (std::size_t i = 0; i < vertex->count; ++i) mesh.colours[i] = {rgb[0][i], rgb[1][i], rgb[2][i]};
  }

  const io::PlyElement* faces = ply->find("face");
  if (faces == nullptr || faces->count == 0) return mesh;
  const io::PlyProperty* indices = faces->find("vertex_indices");
  if (indices == nullptr) indices = faces->find("vertex_index");
  if (indices == nullptr) {
    return parseError(file + ": element 'face' has no 'vertex_indices' (or 'vertex_index') list");
  }
  if (Status s = appendFaces(*faces, *indices, mesh.vertices.size(), file, mesh.triangles); !s.isOk()) return s;
  return mesh;
}

}  // namespace artemis::eval
