// Interoperability: files from writePly must open in Open3D with the same counts and values.
// Runs the system Python (/usr/bin/python3, where Debian's open3d lives) on a small script;
// skips when it is absent, fails under CI=true.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "artemis/io/ply.hpp"
#include "support/test_support.hpp"

namespace artemis::io {
namespace {

constexpr const char* kPython = "/usr/bin/python3";

constexpr const char* kScript = R"(import json, sys
import numpy as np
import open3d as o3d

mesh = o3d.io.read_triangle_mesh(sys.argv[1])
cloud = o3d.io.read_point_cloud(sys.argv[2])
out = {
    "mesh_vertices": np.asarray(mesh.vertices).tolist(),
    "mesh_normals": np.asarray(mesh.vertex_normals).tolist(),
    "mesh_colors": np.asarray(mesh.vertex_colors).tolist(),
    "mesh_triangles": np.asarray(mesh.triangles).tolist(),
    "cloud_points": np.asarray(cloud.points).tolist(),
    "cloud_colors": np.asarray(cloud.colors).tolist(),
}
with open(sys.argv[3], "w") as f:
    json.dump(out, f)
)";

bool open3dAvailable(std::string* why) {
  const std::string probe = std::string(kPython) + " -c \"import open3d\" >/dev/null 2>&1";
  if (std::system(probe.c_str()) == 0) return true;
  *why = std::string(kPython) + " cannot import open3d (install python3-open3d or pip install open3d)";
  return false;
}

struct Mesh {
  std::vector<float> xyz;
  std::vector<float> normals;
  std::vector<std::uint8_t> rgb;
  std::vector<std::uint32_t> triangles;
};

// A 20 x 15 height-field grid: 300 vertices, 532 triangles, all attributes distinct.
Mesh gridMesh() {
  Mesh mesh;
  constexpr std::uint32_t kCols = 20;
  constexpr std::uint32_t kRows = 15;
  for (std::uint32_t r = 0; r < kRows; ++r) {
    for (std::uint32_t c = 0; c < kCols; ++c) {
      const float x = 0.25F * static_cast<float>(c) - 1.3F;
      const float y = 0.1F * static_cast<float>(r) + 1e-4F;
      mesh.xyz.insert(mesh.xyz.end(), {x, y, std::sin(x) * std::cos(y)});
      const float nx = -std::cos(x) * std::cos(y);
      const float ny = std::sin(x) * std::sin(y);
      const float norm = std::sqrt(nx * nx + ny * ny + 1.F);
      mesh.normals.insert(mesh.normals.end(), {nx / norm, ny / norm, 1.F / norm});
      mesh.rgb.insert(mesh.rgb.end(), {static_cast<std::uint8_t>(c * 13), static_cast<std::uint8_t>(r * 17),
                                       static_cast<std::uint8_t>((r * kCols + c) % 256)});
      if (r + 1 < kRows && c + 1 < kCols) {
        const std::uint32_t i = r * kCols + c;
        mesh.triangles.insert(mesh.triangles.end(), {i, i + 1, i + kCols, i + 1, i + kCols + 1, i + kCols});
      }
    }
  }
  return mesh;
}

void expectTriplets(const nlohmann::json& rows, const std::vector<float>& expected, double tolerance,
                    const std::string& what) {
  ASSERT_EQ(rows.size() * 3, expected.size()) << what;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      ASSERT_NEAR(rows[i][k].get<double>(), expected[3 * i + k], tolerance) << what << " " << i << "," << k;
    }
  }
}

void expectColours(const nlohmann::json& rows, const std::vector<std::uint8_t>& expected, const std::string& what) {
  ASSERT_EQ(rows.size() * 3, expected.size()) << what;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      ASSERT_NEAR(rows[i][k].get<double>(), expected[3 * i + k] / 255.0, 1e-12) << what << " " << i << "," << k;
    }
  }
}

TEST(Open3dInterop, MeshAndPointCloudReadBackIdentically) {
  std::string why;
  if (!open3dAvailable(&why)) {
    if (test::runningInCi()) FAIL() << why;
    GTEST_SKIP() << why;
  }
  test::TempDir dir;
  const Mesh mesh = gridMesh();
  ASSERT_EQ(mesh.xyz.size(), 900U);
  ASSERT_EQ(mesh.triangles.size(), 532U * 3);
  ASSERT_TRUE(writePly(dir / "mesh.ply", makePlyMesh({&mesh.xyz, &mesh.normals, &mesh.rgb, &mesh.triangles})).isOk());
  // The cloud goes through the ASCII writer, so both formats are checked against Open3D.
  PlyData cloud = makePlyMesh({&mesh.xyz, nullptr, &mesh.rgb, nullptr});
  cloud.format = PlyFormat::kAscii;
  ASSERT_TRUE(writePly(dir / "cloud.ply", cloud).isOk());

  std::ofstream(dir / "read.py") << kScript;
  const auto json_path = dir / "out.json";
  const std::string command = std::string(kPython) + " " + (dir / "read.py").string() + " " +
                              (dir / "mesh.ply").string() + " " + (dir / "cloud.ply").string() + " " +
                              json_path.string() + " > " + (dir / "log.txt").string() + " 2>&1";
  const int rc = std::system(command.c_str());
  std::ifstream log_file(dir / "log.txt");
  const std::string log((std::istreambuf_iterator<char>(log_file)), std::istreambuf_iterator<char>());
  ASSERT_EQ(rc, 0) << "python failed:\n" << log;
  std::ifstream json_file(json_path);
  const auto result = nlohmann::json::parse(json_file);

  expectTriplets(result["mesh_vertices"], mesh.xyz, 1e-6, "mesh vertex");
  expectTriplets(result["mesh_normals"], mesh.normals, 1e-6, "mesh normal");
  expectColours(result["mesh_colors"], mesh.rgb, "mesh colour");
  const auto& triangles = result["mesh_triangles"];
  ASSERT_EQ(triangles.size(), 532U);
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) ASSERT_EQ(triangles[i][k].get<std::uint32_t>(), mesh.triangles[3 * i + k]);
  }
  expectTriplets(result["cloud_points"], mesh.xyz, 1e-6, "cloud point");
  expectColours(result["cloud_colors"], mesh.rgb, "cloud colour");
}

}  // namespace
}  // namespace artemis::io
