#pragma once
// Voxel-grid downsampling for the evaluator (DESIGN.md: mesh samples and reference at tau / 2):
// one point per occupied voxel, the centroid of the points inside. The same rule as
// artemis::VoxelAccumulator, but parallel, for the 2-10 million samples of an evaluation. Voxels are anchored at the
// origin; keys are 21-bit signed integers per axis, so points with |coordinate| / voxel_size_m >= 2^20 are dropped,
// like non-finite ones.

#include <Eigen/Core>
#include <vector>

namespace artemis::eval::detail {

// Centroids in an order fixed by the input, each summing its points in input order: the result
// is the same on any number of threads.
std::vector<Eigen::Vector3f> voxelCentroids(const std::vector<Eigen::Vector3f>& points, double voxel_size_m);

}  // namespace artemis::eval::detail
