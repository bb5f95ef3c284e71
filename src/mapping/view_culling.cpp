// Stage 2's culling: the voxels a view may see, blocks first (see refinement.hpp).
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

#include "artemis/core/projection.hpp"
#include "artemis/mapping/refinement.hpp"

namespace artemis::mapping {

namespace {

// The view frustum in the camera frame as half-spaces n . p + d >= 0: near, far and the four
// planes through the optical centre and the image's borders.
struct Frustum {
  std::array<Eigen::Vector4f, 6> planes;

  Frustum(const PinholeCamera& c, float near, float far) {
    const PinholeProjector k(c);
    const auto w = static_cast<float>(c.width_px);
    const auto h = static_cast<float>(c.height_px);
    planes = {Eigen::Vector4f(0, 0, 1, -near),          Eigen::Vector4f(0, 0, -1, far),
              Eigen::Vector4f(k.fx, 0, k.cx + 0.5f, 0), Eigen::Vector4f(-k.fx, 0, w - 0.5f - k.cx, 0),
              Eigen::Vector4f(0, k.fy, k.cy + 0.5f, 0), Eigen::Vector4f(0, -k.fy, h - 0.5f - k.cy, 0)};
  }

  // False when the box [lo, hi] (world) lies wholly outside one plane.
  [[nodiscard]] bool mayContain(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Matrix3f& R,
                                const Eigen::Vector3f& t) const {
    std::array<Eigen::Vector3f, 8> corners;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3f p((k & 1) != 0 ? hi.x() : lo.x(), (k & 2) != 0 ? hi.y() : lo.y(),
                              (k & 4) != 0 ? hi.z() : lo.z());
      corners[static_cast<std::size_t>(k)] = R * p + t;
    }
    for (const Eigen::Vector4f& plane : planes) {
      bool all_out = true;
      for (const Eigen::Vector3f& q : corners) {
        if (plane.head<3>().dot(q) + plane.w() >= 0.0f) {
          all_out = false;
          break;
        }
      }
      if (all_out) return false;
    }
    return true;
  }
};

}  // namespace

std::vector<std::uint32_t> voxelsInView(const VoxelMap& map, const PinholeCamera& camera, const Isometry3d& T_W_C,
                                        double max_range_m) {
  const Isometry3d T_C_W = T_W_C.inverse();
  const Eigen::Matrix3f R = T_C_W.linear().cast<float>();
  const Eigen::Vector3f t = T_C_W.translation().cast<float>();
  const Frustum frustum(camera, static_cast<float>(PinholeCamera::kMinDepthM), static_cast<float>(max_range_m));
  const float block_size = map.voxelSize() * static_cast<float>(VoxelMap::kBlockVoxels);
  std::vector<const VoxelMap::Block*> blocks;
  for (const VoxelMap::Block& block : map.blocks()) {
    const Eigen::Vector3f lo = Eigen::Vector3f(static_cast<float>(block.key.x), static_cast<float>(block.key.y),
                                               static_cast<float>(block.key.z)) *
                               block_size;
    if (frustum.mayContain(lo, lo + Eigen::Vector3f::Constant(block_size), R, t)) blocks.push_back(&block);
  }
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> found;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 4), [&](const auto& range) {
    std::vector<std::uint32_t>& mine = found.local();
    for (std::size_t b = range.begin(); b < range.end(); ++b) {
      for (const std::uint32_t index : blocks[b]->voxels) {
        const Voxel& v = map.voxelAt(index);
        if (v.points.empty() || !frustum.mayContain(v.lo, v.hi, R, t)) continue;
        mine.push_back(index);
      }
    }
  });
  std::vector<std::uint32_t> out;
  for (const std::vector<std::uint32_t>& mine : found) out.insert(out.end(), mine.begin(), mine.end());
  std::sort(out.begin(), out.end());  // whatever the threads found first
  return out;
}

}  // namespace artemis::mapping
