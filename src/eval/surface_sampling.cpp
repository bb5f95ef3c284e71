// Area-weighted uniform sampling of a triangle mesh, deterministic for a seed and independent of
// the thread count: per-triangle counts come from systematic rounding of the cumulative area (a
// sequential prefix sum), positions from a counter-based hash of (seed, triangle, k).

#include "surface_sampling.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace artemis::eval {

namespace {

// 12 bytes each: 6 GB of samples, far beyond a street-scale evaluation (and beyond the 32-bit
// indices of the KD-tree).
constexpr std::size_t kMaxSamples = 500'000'000;

// SplitMix64's finaliser: a bijective 64-bit mix, good enough as a counter-based generator.
std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30U)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27U)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31U);
}

// Uniform in [0, 1) from the top 53 bits.
double unitInterval(std::uint64_t bits) {
  return static_cast<double>(bits >> 11U) * 0x1.0p-53;
}

// Area of a triangle with finite corners; 0 for a non-finite or degenerate one.
double triangleArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double area = 0.5 * (b - a).cross(c - a).norm();
  return std::isfinite(area) ? area : 0.0;
}

}  // namespace

namespace detail {

std::string checkTriangleIndices(const MeshArrays& mesh) {
  const std::size_t n = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= n) {
        return "triangle " + std::to_string(t) + " has vertex index " + std::to_string(v) + " but there are " +
               std::to_string(n) + " vertices";
      }
    }
  }
  return {};
}

std::vector<Eigen::Vector3f> sampleSurface(const MeshArrays& mesh, double samples_per_m2, std::size_t min_samples,
                                           std::uint64_t seed,
                                           const std::function<void(std::size_t, std::size_t)>& report,
                                           std::vector<Eigen::Vector3f>* normals,
                                           std::vector<std::uint32_t>* triangles) {
  if (!(samples_per_m2 > 0.0) || !std::isfinite(samples_per_m2)) {
    throw std::invalid_argument("sampleSurface: samples_per_m2 must be > 0, got " + std::to_string(samples_per_m2));
  }
  if (const std::string bad = checkTriangleIndices(mesh); !bad.empty()) {
    throw std::invalid_argument("sampleSurface: " + bad);
  }
  const auto corner = [&](const std::array<std::uint32_t, 3>& tri, std::size_t k) {
    return mesh.vertices[tri[k]].cast<double>();
  };

  // Cumulative area in triangle order: one sequential sum, so the counts are the same on any
  // number of threads.
  const std::size_t n_triangles = mesh.triangles.size();
  std::vector<double> cumulative_area(n_triangles + 1, 0.0);
  for (std::size_t t = 0; t < n_triangles; ++t) {
    const auto& tri = mesh.triangles[t];
    cumulative_area[t + 1] = cumulative_area[t] + triangleArea(corner(tri, 0), corner(tri, 1), corner(tri, 2));
  }
  const double total_area = cumulative_area.back();
  if (!(total_area > 0.0) || !std::isfinite(total_area)) return {};

  const double wanted = std::max(static_cast<double>(min_samples), std::round(total_area * samples_per_m2));
  if (wanted > static_cast<double>(kMaxSamples)) {
    throw std::invalid_argument("sampleSurface: " + std::to_string(total_area) + " m^2 at " +
                                std::to_string(samples_per_m2) + " samples/m^2 needs more than " +
                                std::to_string(kMaxSamples) + " samples");
  }
  const auto total = static_cast<std::size_t>(wanted);
  // Systematic rounding: triangle t owns samples [first[t], first[t + 1]) with
  // first[t] = floor(total * C_t / A + u0). C_n / A is exactly 1, so there are exactly `total`;
  // a zero-area triangle owns none.
  const double u0 = unitInterval(mix64(seed ^ 0x5EEDC0FFEEULL));
  std::vector<std::size_t> first(n_triangles + 1);
  for (std::size_t t = 0; t <= n_triangles; ++t) {
    const double position = static_cast<double>(total) * (cumulative_area[t] / total_area) + u0;
    first[t] = static_cast<std::size_t>(std::floor(position));
  }

  std::vector<Eigen::Vector3f> samples(first.back());
  if (normals != nullptr) normals->assign(samples.size(), Eigen::Vector3f::Zero());
  if (triangles != nullptr) triangles->assign(samples.size(), 0);
  const std::uint64_t seed_mix = mix64(seed);
  detail::chunkedFor(
      samples.size(),
      [&](std::size_t done) {
        if (report) report(done, samples.size());
      },
      [&](std::size_t begin, std::size_t end) {
        // The triangle owning sample `begin`: the last t with first[t] <= begin.
        auto t = static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), begin) - first.begin()) - 1;
        for (std::size_t j = begin; j < end; ++j) {
          while (first[t + 1] <= j) ++t;
          const auto& tri = mesh.triangles[t];
          const std::uint64_t stream = mix64(seed_mix ^ mix64(t));
          const std::uint64_t k = j - first[t];
          // Uniform on the triangle: barycentric (1 - sqrt(r1), sqrt(r1) (1 - r2), sqrt(r1) r2).
          const double s = std::sqrt(unitInterval(mix64(stream + 2 * k)));
          const double r2 = unitInterval(mix64(stream + 2 * k + 1));
          const Eigen::Vector3d p =
              (1.0 - s) * corner(tri, 0) + s * (1.0 - r2) * corner(tri, 1) + s * r2 * corner(tri, 2);
          samples[j] = p.cast<float>();
          if (triangles != nullptr) (*triangles)[j] = static_cast<std::uint32_t>(t);
          if (normals != nullptr) {
            const Eigen::Vector3d n = (corner(tri, 1) - corner(tri, 0)).cross(corner(tri, 2) - corner(tri, 0));
            (*normals)[j] = n.normalized().cast<float>();  // the face has area: it owns a sample
          }
        }
      });
  return samples;
}

}  // namespace detail

std::vector<Eigen::Vector3f> sampleSurface(const MeshArrays& mesh, double samples_per_m2, std::size_t min_samples,
                                           std::uint64_t seed) {
  return detail::sampleSurface(mesh, samples_per_m2, min_samples, seed, {});
}

}  // namespace artemis::eval
