#include "mesh_builder.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace artemis::sim::detail {

using Eigen::Vector3d;

std::uint32_t MeshBuilder::addVertex(const Vector3d& p_S) {
  mesh_.vertices.push_back(p_S.cast<float>());
  return static_cast<std::uint32_t>(mesh_.vertices.size() - 1);
}

void MeshBuilder::addTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  mesh_.triangles.push_back({a, b, c});
  mesh_.face_class.push_back(class_id_);
  mesh_.face_instance.push_back(instance_id_);
  mesh_.face_material.push_back(material_);
  mesh_.face_object.push_back(object_);
}

int MeshBuilder::segments(double length_m, int min_segments) const {
  return std::max(min_segments, static_cast<int>(std::ceil(length_m / max_edge_m_ - 1e-9)));
}

void MeshBuilder::quad(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d) {
  const int nu = segments(std::max((b - a).norm(), (c - d).norm()), 1);
  const int nv = segments(std::max((d - a).norm(), (c - b).norm()), 1);
  const auto first = static_cast<std::uint32_t>(mesh_.vertices.size());
  for (int j = 0; j <= nv; ++j) {
    const double t = static_cast<double>(j) / nv;
    for (int i = 0; i <= nu; ++i) {
      const double s = static_cast<double>(i) / nu;
      addVertex((1 - t) * ((1 - s) * a + s * b) + t * ((1 - s) * d + s * c));
    }
  }
  const auto row = static_cast<std::uint32_t>(nu + 1);
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const std::uint32_t v00 = first + static_cast<std::uint32_t>(j) * row + static_cast<std::uint32_t>(i);
      const std::uint32_t v10 = v00 + 1;
      const std::uint32_t v01 = v00 + row;
      const std::uint32_t v11 = v01 + 1;
      addTriangle(v00, v10, v11);
      addTriangle(v00, v11, v01);
    }
  }
}

void MeshBuilder::frustum(const Eigen::Isometry3d& T_S_P, const Eigen::Vector2d& bottom_lo,
                          const Eigen::Vector2d& bottom_hi, double z0, const Eigen::Vector2d& top_lo,
                          const Eigen::Vector2d& top_hi, double z1, bool with_bottom) {
  // Corners: bottom b0..b3 and top t0..t3 counter-clockwise from above, starting at (lo.x, lo.y).
  const auto corner = [&](const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int k, double z) {
    const double x = (k == 1 || k == 2) ? hi.x() : lo.x();
    const double y = (k >= 2) ? hi.y() : lo.y();
    return Vector3d(T_S_P * Vector3d(x, y, z));
  };
  Vector3d b[4];
  Vector3d t[4];
  for (int k = 0; k < 4; ++k) {
    b[k] = corner(bottom_lo, bottom_hi, k, z0);
    t[k] = corner(top_lo, top_hi, k, z1);
  }
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    quad(b[k], b[n], t[n], t[k]);
  }
  quad(t[0], t[1], t[2], t[3]);
  if (with_bottom) quad(b[0], b[3], b[2], b[1]);
}

void MeshBuilder::box(const Eigen::Isometry3d& T_S_P, const Vector3d& lo, const Vector3d& hi, bool with_bottom) {
  frustum(T_S_P, lo.head<2>(), hi.head<2>(), lo.z(), lo.head<2>(), hi.head<2>(), hi.z(), with_bottom);
}

void MeshBuilder::cylinder(const Eigen::Isometry3d& T_S_P, double radius_m, double z0, double z1) {
  const int n =
      std::clamp(static_cast<int>(std::ceil(2.0 * std::numbers::pi * radius_m / (0.5 * max_edge_m_))), 10, 32);
  const int h = segments(z1 - z0, 1);
  const auto first = static_cast<std::uint32_t>(mesh_.vertices.size());
  for (int j = 0; j <= h; ++j) {
    const double z = z0 + (z1 - z0) * j / h;
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * std::numbers::pi * i / n;
      addVertex(T_S_P * Vector3d(radius_m * std::cos(a), radius_m * std::sin(a), z));
    }
  }
  const auto un = static_cast<std::uint32_t>(n);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::uint32_t v00 = first + static_cast<std::uint32_t>(j) * un + static_cast<std::uint32_t>(i);
      const std::uint32_t v10 = first + static_cast<std::uint32_t>(j) * un + static_cast<std::uint32_t>((i + 1) % n);
      addTriangle(v00, v10, v10 + un);
      addTriangle(v00, v10 + un, v00 + un);
    }
  }
  const std::uint32_t bottom_centre = addVertex(T_S_P * Vector3d(0, 0, z0));
  const std::uint32_t top_centre = addVertex(T_S_P * Vector3d(0, 0, z1));
  const std::uint32_t top_ring = first + static_cast<std::uint32_t>(h) * un;
  for (std::uint32_t i = 0; i < un; ++i) {
    const std::uint32_t next = (i + 1) % un;
    addTriangle(bottom_centre, first + next, first + i);
    addTriangle(top_centre, top_ring + i, top_ring + next);
  }
}

void MeshBuilder::ellipsoid(const Eigen::Isometry3d& T_S_P, const Vector3d& radii) {
  const double r = radii.maxCoeff();
  const int rings = std::clamp(static_cast<int>(std::ceil(std::numbers::pi * r / max_edge_m_)), 6, 20);
  const int n = 2 * rings;
  const std::uint32_t south = addVertex(T_S_P * Vector3d(0, 0, -radii.z()));
  const auto first = static_cast<std::uint32_t>(mesh_.vertices.size());
  for (int j = 1; j < rings; ++j) {
    const double polar = std::numbers::pi * j / rings;  // from the south pole
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * std::numbers::pi * i / n;
      const Vector3d unit(std::sin(polar) * std::cos(a), std::sin(polar) * std::sin(a), -std::cos(polar));
      addVertex(T_S_P * Vector3d(unit.cwiseProduct(radii)));
    }
  }
  const std::uint32_t north = addVertex(T_S_P * Vector3d(0, 0, radii.z()));
  const auto un = static_cast<std::uint32_t>(n);
  const auto ring = [&](int j, int i) {
    return first + static_cast<std::uint32_t>(j - 1) * un + static_cast<std::uint32_t>(i % n);
  };
  for (int i = 0; i < n; ++i) addTriangle(south, ring(1, i + 1), ring(1, i));
  for (int j = 1; j < rings - 1; ++j) {
    for (int i = 0; i < n; ++i) {
      addTriangle(ring(j, i), ring(j, i + 1), ring(j + 1, i + 1));
      addTriangle(ring(j, i), ring(j + 1, i + 1), ring(j + 1, i));
    }
  }
  for (int i = 0; i < n; ++i) addTriangle(north, ring(rings - 1, i), ring(rings - 1, i + 1));
}

}  // namespace artemis::sim::detail
