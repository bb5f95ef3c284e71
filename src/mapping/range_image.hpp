#pragma once
// A scan's returns binned by direction (azimuth x elevation in the sensor frame), so that the rays
// passing near a direction are found with a look at a few bins. Built once per frame from the
// LiDAR-frame points; bins are a little wider than a spinning LiDAR's azimuth step (KITTI's
// HDL-64E: 0.18 deg) and half its widest beam spacing (0.33-0.5 deg).

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::mapping::detail {

// atan2 to within ~1e-5 rad (a minimax polynomial), a few times faster than std::atan2: the
// carver takes two per return and two per map point it tests.
float fastAtan2(float y, float x);

class RangeImage {
 public:
  struct Return {
    Eigen::Vector3f direction;  // unit, sensor frame
    float range_m = 0.0f;
    std::uint32_t bin = 0;
  };

  RangeImage(float azimuth_step_deg, float elevation_step_deg);

  // Bins the finite returns with min_range_m <= range <= max_range_m (spreading the work over the
  // calling TBB arena; the same image at any thread count).
  void build(const std::vector<Eigen::Vector3f>& points_L, float min_range_m, float max_range_m, float grazing_slope);
  // Whether return q (one that forEachNear visited) meets its surface at grazing incidence: the
  // range changes towards the neighbouring returns (the nearer of the two on each side, along the
  // beam and across the beams) by more than grazing_slope times the distance between the rays,
  // along either axis; a return with no neighbour on some axis counts as grazing (unknown).
  // Worked out when first asked (few returns ever are) and kept; thread-safe.
  [[nodiscard]] bool grazing(const Return& q) const;
  // The normal (unit, either sign) of the surface a grazing return q skims, from its nearest
  // neighbouring returns along the beam and across the beams; zero where a side lacks a
  // neighbour or they lie on a line (unknown), and for a return that is not grazing. Worked out
  // with grazing() and kept; thread-safe.
  [[nodiscard]] Eigen::Vector3f skimmedNormal(const Return& q) const;
  [[nodiscard]] bool empty() const { return returns_.empty(); }
  // Takes the room `other` builds in (and leaves it this image's): an image that is not built
  // again needs none, and the one built next frame then finds it ready.
  void adoptScratch(RangeImage& other);
  // Frees what grazing() and skimmedNormal() keep (13 bytes a return, a fifth more for room): for an
  // image only forEachNear() and farthestNear() are asked of any more. Asking grazing() after it,
  // before the next build(), throws std::logic_error.
  void forgetGrazing();
  // Checkpoints (mapping/checkpoint.cpp): the built image; load() into one made with the same steps.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

  // The bin of unit direction d_L (its row may lie outside the image).
  struct Cell {
    int row = 0;
    int col = 0;
  };
  [[nodiscard]] Cell cellOf(const Eigen::Vector3f& d_L) const { return {rowOf(d_L), colOf(d_L)}; }

  // An upper bound on the angle (rad) between unit direction d_L and any return that
  // forEachNear(cellOf(d_L)) visits: their elevations differ by less than 3 elevation steps and
  // their azimuths by less than 2 azimuth steps (5 x 3 bins around d_L's), so the angle is less
  // than the sum of the two, plus fastAtan2's error.
  [[nodiscard]] float nearAngle() const { return 3.0f * elevation_step_ + 2.0f * azimuth_step_ + 1e-4f; }

  // The farthest range among the returns forEachNear(cell) visits (0 when none): one look that
  // settles most questions of whether any ray there goes beyond some range.
  [[nodiscard]] float farthestNear(const Cell& cell) const {
    if (returns_.empty() || cell.row < -2 || cell.row >= rows_ + 2) return 0.0f;
    const int row = std::clamp(cell.row, 0, rows_ - 1);
    return farthest_[static_cast<std::size_t>(row) * static_cast<std::size_t>(cols_) +
                     static_cast<std::size_t>(cell.col)];
  }

  // Calls visit(const Return&) for the returns in the bins around `cell`: 3 in azimuth, 5 in
  // elevation (+-0.5 deg, so that the beams on both sides of a direction between two beams 0.5 deg
  // apart are among them, wherever the bin edges fall).
  template <class Visit>
  void forEachNear(const Cell& cell, Visit&& visit) const {
    if (returns_.empty()) return;
    const std::array<int, 3> columns{wrapped(cell.col - 1), wrapped(cell.col), wrapped(cell.col + 1)};
    for (int r = cell.row - 2; r <= cell.row + 2; ++r) {
      if (r < 0 || r >= rows_) continue;
      for (const int c : columns) {
        const auto bin = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(c);
        for (std::uint32_t k = offsets_[bin]; k < offsets_[bin + 1]; ++k) visit(returns_[k]);
      }
    }
  }

 private:
  // Column c taken around the full turn into [0, cols_) (c % cols_ for c >= 0, without the
  // division: the lookups do this a few hundred thousand times a frame).
  [[nodiscard]] int wrapped(int c) const {
    while (c >= cols_) c -= cols_;
    while (c < 0) c += cols_;
    return c;
  }
  [[nodiscard]] int colOf(const Eigen::Vector3f& d) const;
  [[nodiscard]] int rowOf(const Eigen::Vector3f& d) const;  // may be outside [0, rows_)
  // The least range slope from return k (in bin row, col) to a return in the bins (row + dr, col + dc)
  // for steps 1..reach along (dr, dc) and the opposite way; infinity when there is none.
  [[nodiscard]] float leastSlope(std::size_t k, int row, int col, int dr, int dc, int reach) const;
  // The nearest return (by direction) to return k in the first occupied bins (row + s dr, col + s
  // dc), s = sign * 1..reach; -1 when none.
  [[nodiscard]] std::int64_t nearestAlong(std::size_t k, int row, int col, int dr, int dc, int sign, int reach) const;
  // The tangent of the surface at return k along (dr, dc), from its neighbours on both sides (or
  // one); zero when it has none.
  [[nodiscard]] Eigen::Vector3f tangent(std::size_t k, int row, int col, int dr, int dc, int reach) const;
  // Works out grazing_[k] (and normals_[k] for a grazing return).
  std::uint8_t classify(std::size_t k) const;
  void findFarthest();

  float azimuth_step_;    // rad
  float elevation_step_;  // rad
  float elevation_min_ = 0.0f;
  int cols_ = 0;
  int rows_ = 0;
  std::vector<std::uint32_t> offsets_;  // CSR over bins, row-major
  std::vector<Return> returns_;
  struct Angles {
    Return ret;
    float elevation = 0.0f;
    int col = 0;
    bool valid = false;
  };
  std::vector<Angles> angles_;         // per input point (scratch)
  std::vector<std::uint32_t> bin_of_;  // per kept return (scratch)
  std::vector<std::uint32_t> fill_;
  std::vector<float> farthest_;  // per bin: the farthest return in the bins forEachNear visits
  std::vector<float> scratch_far_;
  float grazing_slope_ = 0.0f;
  // Per return: 0 not worked out yet, 1 not grazing, 2 grazing.
  std::unique_ptr<std::atomic<std::uint8_t>[]> grazing_;
  std::unique_ptr<Eigen::Vector3f[]> normals_;  // per return, set before grazing_ says 2 (release)
  std::size_t grazing_capacity_ = 0;
};

}  // namespace artemis::mapping::detail
