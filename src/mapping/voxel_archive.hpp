#pragma once
// Internal to the mapping module: a voxel's fields in an archive, after its vertex ids (which
// checkpoints write as they are and tile state files as the tile numbers them), in one order for
// both.

#include "artemis/core/archive.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis::mapping::detail {

inline void saveVoxelFields(ArchiveWriter& out, const Voxel& v) {
  out.array(v.points);
  out.array(v.sub_cells);
  out.array(v.evidence);
  out.value(v.lo);
  out.value(v.hi);
  out.value(v.occupied);
  out.value(v.points_when_meshed);
  out.value(v.active_frame);
  out.value(v.hit_frame);
  out.value(v.carved_frame);
  out.value(v.plane_normal);
  out.value(v.plane_points);
  out.value(v.meshed_frame);
}

// Reads what saveVoxelFields wrote; fails unless the points, sub-cells and evidence match the
// voxel's vertices (read before).
inline void loadVoxelFields(ArchiveReader& in, Voxel& v) {
  in.array(v.points);
  in.array(v.sub_cells);
  in.array(v.evidence);
  in.value(v.lo);
  in.value(v.hi);
  in.value(v.occupied);
  in.value(v.points_when_meshed);
  in.value(v.active_frame);
  in.value(v.hit_frame);
  in.value(v.carved_frame);
  in.value(v.plane_normal);
  in.value(v.plane_points);
  in.value(v.meshed_frame);
  if (v.points.size() != v.vertices.size() || v.sub_cells.size() != v.vertices.size() ||
      v.evidence.size() != v.vertices.size()) {
    in.fail("a voxel's points, sub-cells and evidence do not match its vertices");
  }
}

}  // namespace artemis::mapping::detail
