#pragma once
// Semantic rendering's highlight (paper §III-C, Fig. 7): the vertices whose class is one of the
// classes a query matched take that class's highlight colour; everything else keeps its texture.
// The classes are plain ids (a vocabulary's ClassId), so any mesh file with a per-vertex class can
// be highlighted.
//
// A vertex's class is the class it was labelled with (its most probable one, `class_id` in the
// run's mesh.ply). A pixel is highlighted when the vertex of its face nearest to it (the largest
// barycentric weight) is: a face between a car and the road is split where the classes change,
// as interpolating the vertices' classes would split it.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "artemis/core/image.hpp"
#include "artemis/render/rasterizer.hpp"

namespace artemis::render {

using Rgb8 = std::array<std::uint8_t, 3>;

// The colour of the k-th queried class (0-based), distinct from each other and from road and
// building greys; it cycles after kHighlightColours.
inline constexpr std::size_t kHighlightColours = 6;
Rgb8 highlightColour(std::size_t k);

// Per vertex: 0 when its class is none of `classes`, else 1 + the class's position in `classes`.
std::vector<std::uint8_t> vertexHighlight(std::span<const std::uint8_t> vertex_class,
                                          std::span<const std::uint8_t> classes);

struct ShadeParams {
  Rgb8 background = {255, 255, 255};
  Rgb8 untextured = {200, 200, 200};  // the surface colour of a mesh without vertex colours
  float highlight_weight = 0.75f;     // highlight colour's share in a highlighted pixel
  // Untextured surfaces are shaded by the angle between face normal and viewing ray (the shape
  // shows); textured ones are shown as captured.
  float ambient = 0.35f;
};

struct ShadedPicture {
  ImageU8 image;  // 3 channels, sRGB
  ImageU8 mask;   // 1 channel: 255 where the visible surface is highlighted, else 0
  std::size_t covered_pixels = 0;
  std::size_t highlighted_pixels = 0;
};

// The picture `picture` of `mesh` (rasterized from `view`, with the mesh's colours read as sRGB in
// 0..1) as an 8-bit image, with the surfaces of `vertex_highlight` (from vertexHighlight; may be
// empty: no highlight) in their class's colour.
ShadedPicture shade(const MeshArrays& mesh, const Picture& picture, const View& view,
                    std::span<const std::uint8_t> vertex_highlight, const ShadeParams& params = {});

}  // namespace artemis::render
