#pragma once
// Small holes in the finished mesh, closed. Each voxel triangulates its own points with a rim of
// its neighbours' and keeps the faces whose centroid it holds; two neighbours' triangulations of
// the strip along their border differ, so where a sparse surface (the road beyond a few metres,
// where the scan rings lie tens of centimetres apart) crosses a voxel border, a sliver that each
// voxel left to the other stays open. Seen from above, the road is crossed by lines of such
// cracks, and rays of the scans that built it pass through them ("hole" in `artemis eval rays`).
//
// A hole is a loop of boundary edges (an edge that one face uses and no face uses the other way):
//   - of 3 to max_loop_edges edges, none longer than max_edge_m (the mesher's longest face edge:
//     the gap is one the mesher would have spanned);
//   - that runs against the faces around it (the loop's area vector points away from their mean
//     normal): the outline of a small island of faces runs with them and is not a hole;
//   - whose faces around agree on which way the surface faces (the mean of their unit normals at
//     least min_normal_agreement long): foliage, whose faces point every way, keeps its gaps;
//   - whose corners lie within max_plane_distance_m of the plane through their centre that faces
//     like the faces around (the mean of their normals): a kerb, a car's sill over the road, or a
//     step between two surfaces is a real gap and stays open.
// Where two holes touch at a vertex (two boundary edges leave it), a loop goes on by the edge met
// first turning counter-clockwise from the one it came by: around the same hole.
// It is closed by ear clipping in its plane with faces wound like the faces around, each of whose
// edges is at most max_edge_m, none already in the mesh (the result stays an oriented manifold
// where it was one).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "artemis/mapping/semantic_mesh.hpp"

namespace artemis::mapping {

struct HoleFillParams {
  bool enabled = true;
  int max_loop_edges = 8;
  double max_plane_distance_m = 0.05;
  double min_normal_agreement = 0.75;  // |mean of the unit normals of the faces around|, at least
};

struct HoleFillStats {
  std::size_t boundary_edges = 0;
  std::size_t loops = 0;   // closed boundary loops of at most max_loop_edges edges
  std::size_t filled = 0;  // of those, closed
  std::size_t faces = 0;   // faces added
  // Loops left open, by the first reason found.
  std::size_t long_edges = 0;  // an edge longer than max_edge_m
  std::size_t islands = 0;     // the loop runs with the faces around: an island's outline
  std::size_t rough = 0;       // the faces around point different ways (foliage)
  std::size_t bumpy = 0;       // a corner farther than max_plane_distance_m from the plane
  std::size_t unclipped = 0;   // no triangulation with short edges, or one that would repeat an edge
  double ms = 0.0;

  // Adds another call's figures (tiles close their holes one by one).
  HoleFillStats& operator+=(const HoleFillStats& o) {
    boundary_edges += o.boundary_edges;
    loops += o.loops;
    filled += o.filled;
    faces += o.faces;
    long_edges += o.long_edges;
    islands += o.islands;
    rough += o.rough;
    bumpy += o.bumpy;
    unclipped += o.unclipped;
    ms += o.ms;
    return *this;
  }
};

// The faces that close the small holes of the mesh (`faces` over `positions`); `max_edge_m` is the
// mesher's longest face edge (MesherParams::max_edge_m), which no loop or new face may exceed.
std::vector<Face> holeFillingFaces(const std::vector<Face>& faces, const std::vector<Eigen::Vector3f>& positions,
                                   double max_edge_m, const HoleFillParams& params, HoleFillStats* stats = nullptr);

}  // namespace artemis::mapping
