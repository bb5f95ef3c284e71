#pragma once
// Geometric accuracy of a reconstructed mesh against a reference (DESIGN.md, "How results are
// measured"): sample the mesh uniformly (>= 400 samples per m^2, at least 2 million), voxel-
// downsample samples and reference at tau/2; precision = share of mesh samples within tau of the
// reference, counting only samples inside the reference's bounding box padded by 1 m; recall =
// share of reference points within tau of the mesh samples; F1 their harmonic mean.
//
// The evaluator reads plain arrays (or files), never the mapper's internals, so it scores any
// tool's mesh.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/status.hpp"

namespace artemis::eval {

struct MeshArrays {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // empty for a point cloud
  std::vector<std::array<std::uint8_t, 3>> colours;     // sRGB per vertex when the file has them, else empty
};

struct GeometryParams {
  std::vector<double> taus_m = {0.1, 0.2};
  double samples_per_m2 = 400.0;
  std::size_t min_samples = 2'000'000;
  double crop_padding_m = 1.0;
  std::uint64_t seed = 1;  // of the surface sampling; results do not depend on thread count
};

// Ok, or invalidArgument naming the first bad value: no tau or a tau that is not > 0, a density
// that is not > 0, a negative padding.
Status validate(const GeometryParams& params);

struct GeometryScore {
  double tau_m = 0.0;
  double precision = 0.0;
  double recall = 0.0;
  double f1 = 0.0;
  std::size_t mesh_points = 0;       // downsampled mesh samples inside the crop
  std::size_t reference_points = 0;  // downsampled reference points
};

// Uniform samples on the triangles (area-weighted, deterministic for a seed). Zero-area and
// non-finite triangles get none. Exactly max(min_samples, round(area * samples_per_m2)) samples
// when some triangle has area; none otherwise. Each triangle gets its share of the total area
// (systematic rounding: its count differs from area_i * density by less than one) at positions
// drawn from a hash of (seed, triangle, k), so the result does not depend on thread count.
// Throws std::invalid_argument for a vertex index out of range, a density that is not > 0, or
// more than 500 million samples.
std::vector<Eigen::Vector3f> sampleSurface(const MeshArrays& mesh, double samples_per_m2, std::size_t min_samples,
                                           std::uint64_t seed);

// A reference given as a mesh is sampled like the evaluated mesh; a cloud is used as it is.
// `seen`, when not empty, crops the reference to the part the sensor saw (for the simulator's
// ground truth, which also covers roofs, undersides and backs no scan reached): a reference sample
// is kept when a seen point lies within `seen_radius_m` of it and, for a mesh reference, within
// `seen_plane_tolerance_m` of the sample's own plane (measured along the face normal), so that
// the far side of a thin object (a pole, a tyre, a fence) is not counted as seen because of the
// points on its near side. A cloud reference has no normals and uses the radius alone.
struct Reference {
  MeshArrays geometry;
  std::vector<Eigen::Vector3f> seen;
  double seen_radius_m = 0.25;
  double seen_plane_tolerance_m = 0.1;
};

// Reports the work of evaluateGeometry as it goes: `stage` names the step ("sampling the mesh",
// "precision at 0.10 m", ...), `done` of `total` its items. Always called from the calling
// thread, between chunks of parallel work.
using Progress = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

// Scores `mesh` against `reference` for every tau (in the order given). Errors: empty mesh or
// reference, no triangle with area in the mesh, a vertex index out of range, a tau that is not > 0,
// no reference point left after the `seen` crop. Non-finite reference points are ignored.
// Precision is 0 when no mesh sample lies in the crop box; F1 is 0 when precision + recall is 0.
// Runs in parallel with TBB (in the caller's task arena); the scores are the same for any number
// of threads. About 2 s for 2 million mesh samples against 2.4 million reference points on 2 cores.
Result<std::vector<GeometryScore>> evaluateGeometry(const MeshArrays& mesh, const Reference& reference,
                                                    const GeometryParams& params, const Progress& progress = {});

// Faces of a mesh that join two classes of a labelled reference mesh (the simulator's gt/mesh.ply,
// whose faces carry class ids): each vertex takes the class of the nearest reference surface
// sample (400 per m^2) within `max_distance_m`, and a face joins a and b when its corners hold
// both. How often a mesh glues a car to the road under it. Errors: face classes that do not match
// the reference's faces, a reference without area, a vertex index out of range.
struct ClassBoundaryFaces {
  std::uint16_t a = 0;
  std::uint16_t b = 0;
  std::size_t faces = 0;          // of the mesh
  std::size_t joining = 0;        // with a corner of class a and one of class b
  std::size_t faces_with_a = 0;   // with a corner of class a
  std::size_t unlabelled_vertices = 0;  // no reference surface within max_distance_m
  double share = 0.0;             // joining / faces_with_a (0 without such faces)
};
Result<ClassBoundaryFaces> classBoundaryFaces(const MeshArrays& mesh, const MeshArrays& reference,
                                              const std::vector<std::uint16_t>& reference_face_classes,
                                              std::uint16_t a, std::uint16_t b, double max_distance_m = 0.2);
// The face property `class_id` of a PLY mesh (empty when the file has none).
Result<std::vector<std::uint16_t>> readFaceClasses(const std::filesystem::path& path);

// Reads a PLY as vertices (x, y, z) and, when it has them, vertex colours (red, green, blue, as
// 8-bit values) and triangles (polygons are fanned).
// Errors name the file and the problem.
Result<MeshArrays> readMeshArrays(const std::filesystem::path& path);

}  // namespace artemis::eval
