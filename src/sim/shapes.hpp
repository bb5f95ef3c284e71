#pragma once
// Shapes of the street's road users, shared by the parked ones (scene.cpp) and the moving ones
// (traffic.cpp). Each appends faces to a MeshBuilder with its current tag; materials are set here.
// Object frames: x forward, y left, z up, origin on the ground (cars: the footprint's centre).

#include <Eigen/Geometry>

#include "mesh_builder.hpp"

namespace artemis::sim::detail {

// The frame at p turned by yaw about z.
Eigen::Isometry3d frameAt(const Eigen::Vector3d& p, double yaw);

// Car body: lower box, cabin frustum, four wheels. Variant 0 sedan, 1 hatchback, 2 van.
void carShape(MeshBuilder& builder, const Eigen::Isometry3d& T, int variant, double len, double width);
void truckShape(MeshBuilder& builder, const Eigen::Isometry3d& T, double len);
void wheels(MeshBuilder& builder, const Eigen::Isometry3d& T, double axle_x, double outer_y, double radius,
            double tyre_width);

// A standing or walking person of height H facing the frame's x axis.
void personShape(MeshBuilder& builder, const Eigen::Vector3d& base, double yaw, double height_m);

// A bicycle (1.75 m long) along the frame's x axis, without a rider.
void bicycleShape(MeshBuilder& builder, const Eigen::Isometry3d& T);

// A rider sitting on bicycleShape's saddle, hands on its handlebar.
void riderShape(MeshBuilder& builder, const Eigen::Isometry3d& T, double height_m);

}  // namespace artemis::sim::detail
