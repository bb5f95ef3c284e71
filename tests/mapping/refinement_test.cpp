// Stage 2's texture refinement on scenes with known answers: culling by blocks and voxels, a
// vertex hidden behind a nearer surface gets no colour from that view, the exposure gain, and a
// kept view's revisit.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "artemis/mapping/mapper.hpp"
#include "artemis/mapping/refinement.hpp"
#include "camera_scenes.hpp"

namespace artemis::mapping {
namespace {

using test::wall;
// The image: a grey wall (sRGB 128), the board's pixels (|u - cx|, |v - cy| <= 20) red.
ImageU8 picture(std::uint8_t wall_grey = 128) {
  ImageU8 image(200, 100, 3, wall_grey);
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 200; ++u) {
      if (std::abs(u - 99.5) <= 20.0 && std::abs(v - 49.5) <= 20.0) {
        image.at(u, v, 0) = 255;
        image.at(u, v, 1) = 0;
        image.at(u, v, 2) = 0;
      }
    }
  }
  return image;
}

// A wall at 10 m and a 2 m board at 5 m in front of it, scanned and meshed.
std::unique_ptr<Mapper> scene(const MapperParams& params = {}) {
  auto mapper = std::make_unique<Mapper>(params);
  PointCloud points = wall(10.05f, 4.0f, 2.0f);
  const PointCloud board = wall(5.05f, 1.0f, 1.0f);
  points.points.insert(points.points.end(), board.points.begin(), board.points.end());
  mapper->integrate(points, Isometry3d::Identity());
  mapper->finish();
  return mapper;
}

TEST(TextureRefinement, AVertexHiddenBehindANearerSurfaceGetsNoColour) {
  const auto mapper = scene();
  CameraView view = test::forwardCamera();
  view.image = picture();
  const RefinementStats stats = mapper->refine({&view}, Isometry3d::Identity());
  const SemanticMesh& mesh = mapper->mesh();
  EXPECT_GT(stats.faces_rendered, 1000u);
  std::size_t hidden = 0, wall_seen = 0, board_seen = 0;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f p = mesh.positions()[v];
    if (p.x() > 7.0f) {
      // The wall behind the board (its shadow in the view reaches |y|, |z| ~ 1.9 m at 10 m; the
      // board's mesh stops a little short of its outermost points) must stay uncoloured although
      // those pixels are red; the wall elsewhere in view is grey.
      if (std::abs(p.y()) < 1.6f && std::abs(p.z()) < 1.6f) {
        EXPECT_FALSE(mesh.hasColour(v)) << p.transpose();
        ++hidden;
      } else if (std::abs(p.y()) > 2.2f) {
        if (mesh.hasColour(v)) {
          EXPECT_NEAR(mesh.colourMean(v).x(), 0.2158f, 0.01f);  // sRGB 128 in linear RGB
          ++wall_seen;
        }
      }
    } else if (std::abs(p.y()) < 0.9f && std::abs(p.z()) < 0.9f) {
      ASSERT_TRUE(mesh.hasColour(v)) << p.transpose();
      EXPECT_NEAR(mesh.colourMean(v).x(), 1.0f, 0.01f);
      EXPECT_NEAR(mesh.colourMean(v).y(), 0.0f, 0.01f);
      ++board_seen;
    }
  }
  EXPECT_GT(hidden, 500u);
  EXPECT_GT(wall_seen, 500u);
  EXPECT_GT(board_seen, 300u);  // 18 x 18 vertices

  // Without the reliability (plain averaging), the hidden wall does take the board's red.
  MapperParams plain;
  plain.refinement.reliability = false;
  const auto plain_mapper = scene(plain);
  plain_mapper->refine({&view}, Isometry3d::Identity());
  const SemanticMesh& plain_mesh = plain_mapper->mesh();
  std::size_t stained = 0;
  for (std::uint32_t v = 0; v < plain_mesh.vertexCount(); ++v) {
    const Eigen::Vector3f p = plain_mesh.positions()[v];
    if (p.x() > 7.0f && std::abs(p.y()) < 1.5f && std::abs(p.z()) < 1.5f && plain_mesh.hasColour(v) &&
        plain_mesh.colourMean(v).x() > 0.9f) {
      ++stained;
    }
  }
  EXPECT_GT(stained, 500u);
}

TEST(TextureRefinement, ExposureGainIsEstimatedAgainstTheMap) {
  const auto mapper = scene();
  CameraView view = test::forwardCamera();
  const SemanticMesh& mesh = mapper->mesh();
  view.image = picture(128);
  mapper->refine({&view}, Isometry3d::Identity());
  // The same scene, the camera's exposure 1.5x brighter in linear terms: sRGB 128 -> 155.
  view.image = picture(155);
  const RefinementStats stats = mapper->refine({&view}, Isometry3d::Identity());
  EXPECT_NEAR(stats.gain, 0.3277 / 0.2158, 0.01);  // linear 155 / linear 128
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f p = mesh.positions()[v];
    if (p.x() > 7.0f && std::abs(p.y()) > 2.2f && mesh.hasColour(v)) {
      ASSERT_NEAR(mesh.colourMean(v).y(), 0.2158f, 0.01f);  // unchanged: the gain was taken out
    }
  }
}

TEST(TextureRefinement, CullingKeepsTheVoxelsInViewOnly) {
  Mapper mapper{MapperParams{}};
  PointCloud points = wall(10.05f, 4.0f, 2.0f);         // ahead: in view
  const PointCloud behind = wall(-10.05f, 4.0f, 2.0f);  // behind the camera
  points.points.insert(points.points.end(), behind.points.begin(), behind.points.end());
  mapper.integrate(points, Isometry3d::Identity());
  const CameraView view = test::forwardCamera();
  const auto in_view = voxelsInView(mapper.voxels(), view.camera, view.T_L_C, 80.0);
  ASSERT_FALSE(in_view.empty());
  std::size_t ahead = 0;
  for (const std::uint32_t index : in_view) {
    const Voxel& v = mapper.voxels().voxelAt(index);
    EXPECT_GT(v.hi.x(), 0.0f);
    ++ahead;
  }
  // The whole front wall is within the view (+-40 px half-width at 10 m covers +-4 m... and more).
  std::size_t front_voxels = 0;
  for (const auto& key : mapper.voxels().keys()) front_voxels += key.x > 0 ? 1 : 0;
  EXPECT_EQ(ahead, front_voxels);
}

// The revisit scene: a board at 5 m and the left half of a wall at 10 m, with one 0.1 m cell in
// 16 left empty, scanned, meshed and refined with the view kept; then the empty cells, the right
// half of the wall (partly behind the board) and a patch at 8 m in front of the left half.
struct RevisitScene {
  std::unique_ptr<Mapper> mapper;
  CameraView view = test::forwardCamera();
  ViewMemory memory;
  std::vector<Eigen::Vector3f> variance_before;  // of the vertices the refinement saw
  RefinementStats stats;                         // the revisit's
};

RevisitScene revisitScene(int threads) {
  RevisitScene scene;
  MapperParams params;
  params.threads = threads;
  scene.mapper = std::make_unique<Mapper>(params);
  const auto gap = [](const Eigen::Vector3f& p) {
    const auto cell = [](float a) { return static_cast<int>(std::floor(a / 0.1f + 1e-4f)); };
    return p.y() < 0.0f && cell(p.y() + 4.0f) % 4 == 1 && cell(p.z() + 2.0f) % 4 == 1;
  };
  PointCloud first;
  PointCloud later;
  for (const auto& p : wall(10.05f, 4.0f, 2.0f).points) (p.y() < 0.0f && !gap(p) ? first : later).points.push_back(p);
  const PointCloud board = wall(5.05f, 1.0f, 1.0f);
  first.points.insert(first.points.end(), board.points.begin(), board.points.end());
  for (const auto& p : wall(8.05f, 0.5f, 0.5f).points) later.points.emplace_back(p.x(), p.y() - 2.3f, p.z());
  scene.mapper->integrate(first, Isometry3d::Identity());
  scene.mapper->finish();
  scene.view.image = picture();
  scene.mapper->refine({&scene.view, true, nullptr, nullptr, &scene.memory}, Isometry3d::Identity());
  const SemanticMesh& mesh = scene.mapper->mesh();
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) scene.variance_before.push_back(mesh.colourVariance(v));
  scene.mapper->integrate(later, Isometry3d::Identity());
  scene.mapper->finish();
  scene.stats = scene.mapper->revisit(scene.view, scene.memory);
  return scene;
}

// A view kept after its refinement colours, when revisited, the vertices scanned since that it
// saw where its reference depth had the same surface or none: not those hidden behind a nearer
// surface, nor those in front of one (a new occluder or a new surface, r_geom cannot tell), and
// never a vertex twice.
TEST(TextureRefinement, ARevisitColoursWhatWasScannedAfterTheRefinement) {
  RevisitScene scene = revisitScene(0);
  const Mapper& mapper = *scene.mapper;
  const ViewMemory& memory = scene.memory;
  ASSERT_FALSE(memory.empty());
  const SemanticMesh& mesh = mapper.mesh();
  EXPECT_EQ(memory.vertices, scene.variance_before.size());
  ASSERT_EQ(memory.depth.width(), 200);
  // The reference depth in 2 mm steps: the board ahead, the wall's left half, nothing on the right
  // (y = -3 m at 10.05 m is pixel u = 99.5 + 100 * 3 / 10.05).
  EXPECT_NEAR(memory.depth.at(100, 50), 5.05 / 0.002, 2.0);
  EXPECT_NEAR(memory.depth.at(129, 50), 10.05 / 0.002, 2.0);
  EXPECT_EQ(memory.depth.at(60, 50), ViewMemory::kNoDepth);
  ASSERT_GT(mesh.vertexCount(), memory.vertices);

  std::size_t filled = 0, seen = 0, hidden = 0, in_front = 0;
  for (std::uint32_t v = memory.vertices; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f p = mesh.positions()[v];
    if (p.x() < 9.0f) {
      EXPECT_FALSE(mesh.hasColour(v)) << p.transpose();  // the patch in front of the known wall
      ++in_front;
    } else if (std::abs(p.y()) < 1.6f && std::abs(p.z()) < 1.6f) {
      EXPECT_FALSE(mesh.hasColour(v)) << p.transpose();  // behind the board
      ++hidden;
    } else if (std::abs(p.y()) > 2.2f) {
      // The wall's grey, not the board's red: in the left half's gaps against the depth of the
      // wall around them, on the right where the view had no depth.
      ASSERT_TRUE(mesh.hasColour(v)) << p.transpose();
      EXPECT_NEAR(mesh.colourMean(v).x(), 0.2158f, 0.01f);
      ++(p.y() < 0.0f ? filled : seen);
    }
  }
  EXPECT_GT(filled, 40u);
  EXPECT_GT(seen, 500u);
  EXPECT_GT(hidden, 200u);
  EXPECT_GT(in_front, 50u);
  EXPECT_GE(scene.stats.vertices_updated, filled + seen);
  EXPECT_FALSE(scene.stats.voxels.empty());
  // What the refinement coloured is left as it was.
  for (std::uint32_t v = 0; v < memory.vertices; ++v) {
    ASSERT_EQ(mesh.colourVariance(v), scene.variance_before[v]) << v;
  }
  // A second revisit finds nothing new to colour.
  EXPECT_EQ(scene.mapper->revisit(scene.view, memory).vertices_updated, 0u);
  // A memory from another image size is refused, an empty one does nothing.
  ViewMemory wrong = memory;
  wrong.depth = ImageU16(10, 10, 1);
  EXPECT_THROW(scene.mapper->revisit(scene.view, wrong), std::invalid_argument);
  EXPECT_EQ(scene.mapper->revisit(scene.view, ViewMemory{}).vertices_updated, 0u);
}

TEST(TextureRefinement, ARevisitDoesNotDependOnTheThreadCount) {
  const RevisitScene one = revisitScene(1);
  const RevisitScene two = revisitScene(2);
  const SemanticMesh& a = one.mapper->mesh();
  const SemanticMesh& b = two.mapper->mesh();
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  EXPECT_EQ(one.stats.vertices_updated, two.stats.vertices_updated);
  EXPECT_EQ(one.stats.voxels, two.stats.voxels);
  for (std::uint32_t v = 0; v < a.vertexCount(); ++v) {
    ASSERT_EQ(a.colourMean(v), b.colourMean(v)) << v;
    ASSERT_EQ(a.colourVariance(v), b.colourVariance(v)) << v;
  }
}

}  // namespace
}  // namespace artemis::mapping
