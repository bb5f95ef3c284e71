#include "delaunay.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <utility>

namespace artemis::mapping::detail {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, DataStructure>;
}  // namespace

std::vector<std::array<int, 3>> delaunay2d(const std::vector<Eigen::Vector2d>& points) {
  std::vector<std::array<int, 3>> out;
  if (points.size() < 3) return out;
  // Point by point, each located from the last one inserted: the voxel's points come in scan
  // order, so successive points are close, and for the few dozen points of a voxel this beats
  // the range constructor's Hilbert sort.
  Delaunay triangulation;
  Delaunay::Face_handle hint;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t before = triangulation.number_of_vertices();
    const Delaunay::Vertex_handle v = triangulation.insert(Kernel::Point_2(points[i].x(), points[i].y()), hint);
    if (triangulation.number_of_vertices() > before) v->info() = static_cast<int>(i);  // else a repeat: keep the first
    hint = v->face();
  }
  out.reserve(2 * points.size());
  for (auto f = triangulation.finite_faces_begin(); f != triangulation.finite_faces_end(); ++f) {
    out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return out;
}

}  // namespace artemis::mapping::detail
