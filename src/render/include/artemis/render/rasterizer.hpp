#pragma once
// A CPU triangle rasterizer for pictures and reference depth (DESIGN.md, module `render`): plain
// mesh arrays in, per pixel the nearest face's depth along the optical axis, its id and, when the
// mesh has vertex colours, the colour interpolated across the face. It draws any mesh file, not
// only the mapper's.
//
// Pixel centres are at integer coordinates (PinholeCamera's convention). Depth is interpolated
// perspective-correctly (1/z is affine in screen space). A face with a vertex closer than near_m
// or farther than far_m is not drawn (mesh faces are centimetres to decimetres wide; no clipping).
// Faces are drawn in horizontal strips of rows, one strip per task, so pixels are written by one
// thread only; equal depths go to the lower face id. The picture does not depend on the thread
// count.

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/camera.hpp"
#include "artemis/core/image.hpp"
#include "artemis/core/transform.hpp"

namespace artemis::render {

inline constexpr std::uint32_t kNoFace = std::numeric_limits<std::uint32_t>::max();

struct MeshArrays {
  std::span<const Eigen::Vector3f> positions;               // world frame
  std::span<const std::array<std::uint32_t, 3>> triangles;  // vertex indices
  std::span<const Eigen::Vector3f> colours;                 // per vertex, 0..1 (any colour space); may be empty
};

struct View {
  PinholeCamera camera;
  Isometry3d T_W_C = Isometry3d::Identity();  // camera (x right, y down, z forward) into world
  double near_m = 0.05;
  double far_m = 1000.0;
};

struct Picture {
  ImageF32 depth;                   // z in the camera frame (m); +inf where no face
  std::vector<std::uint32_t> face;  // row-major, kNoFace where no face
  ImageF32 colour;                  // 3 channels when the mesh has colours, else empty
  [[nodiscard]] std::uint32_t faceAt(int u, int v) const {
    return face[static_cast<std::size_t>(v) * static_cast<std::size_t>(depth.width()) + static_cast<std::size_t>(u)];
  }
};

// Draws `faces` of `mesh` (all faces when `faces` is empty) from `view`. Indices out of range and
// non-finite vertices make a face invisible, never a crash.
Picture rasterize(const MeshArrays& mesh, const View& view, std::span<const std::uint32_t> faces = {});

// Draws points as screen-facing discs of world radius `radius_m` (at least half a pixel), each of
// its point's colour, the nearest point winning per pixel (ties: the lower index); `face` holds
// the point index. This is what a coloured point cloud looks like rendered: the baseline a mesh's
// texture is compared with. Points behind the camera or non-finite are left out.
Picture splat(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> colours, double radius_m,
              const View& view);

}  // namespace artemis::render
