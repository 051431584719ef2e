// MeshRender without OpenGL: mesh from depth, the camera matrices (evaluated in double the way OpenGL
// applies them) and the PLY file.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Camera.h"
#include "Common/Depth.h"
#include "Common/Frame.h"
#include "Common/Options.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/MeshPly.h"
#include "Mesh/MeshProjection.h"
#include "TestPaths.h"

namespace {

const double kInf = std::numeric_limits<double>::infinity();

vs::Mat3 rotation(double ax, double ay, double az) {
  vs::Mat3 x = vs::Mat3::identity(), y = vs::Mat3::identity(), z = vs::Mat3::identity();
  x[1][1] = std::cos(ax), x[1][2] = -std::sin(ax), x[2][1] = std::sin(ax), x[2][2] = std::cos(ax);
  y[0][0] = std::cos(ay), y[0][2] = std::sin(ay), y[2][0] = -std::sin(ay), y[2][2] = std::cos(ay);
  z[0][0] = std::cos(az), z[0][1] = -std::sin(az), z[1][0] = std::sin(az), z[1][1] = std::cos(az);
  return z * y * x;
}

// A camera with skew, an unequal aspect, an off-centre principal point and a world position far from
// the origin, so that precision problems would show.
vs::Camera skewedCamera(const vs::Vec3& centre, double ax, double ay, double az) {
  vs::Camera camera;
  camera.name = "test";
  camera.K[0][0] = 520.0, camera.K[0][1] = 3.5, camera.K[0][2] = 79.3;
  camera.K[1][1] = 505.0, camera.K[1][2] = 61.8;
  camera.R = rotation(ax, ay, az);
  camera.t = centre;
  return camera;
}

// A skewed camera within 10 units of `near` on each axis, turned by up to 0.1 radian about each axis.
vs::Camera skewedCameraNear(const vs::Vec3& near, std::mt19937& random) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const vs::Vec3 offset{unit(random), unit(random), unit(random)};
  const double ax = 0.1 * unit(random), ay = 0.1 * unit(random), az = 0.1 * unit(random);
  return skewedCamera(near + offset * 10.0, ax, ay, az);
}

vs::DepthRange range8(double znear, double zfar) {
  vs::DepthRange range;
  range.znear = znear;
  range.zfar = zfar;
  range.bitDepth = 8;
  return range;
}

// The world point a mesh vertex stands for (finite vertices only).
vs::Vec3 vertexWorld(const vs::Camera& camera, const float* vertex) {
  const vs::Vec3 xc = vs::inverse(camera.K) * vs::Vec3(vertex[0], vertex[1], vertex[2]);
  return camera.cameraToWorld(xc / double(vertex[3]));
}

TEST(MeshDepth, GridHasEveryStepTheLastPixelAndTheHalfPixelBorder) {
  const vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  vs::MeshOptions options;
  options.gridStep = 4;
  const vs::DepthMeshBuilder builder(camera, range8(100, 200), 10, 7, options);
  vs::DepthMesh mesh;
  builder.build(vs::Plane(10, 7, 128), mesh);
  EXPECT_EQ(mesh.gridU, (std::vector<double>{-0.5, 0, 4, 8, 9, 9.5}));
  EXPECT_EQ(mesh.gridV, (std::vector<double>{-0.5, 0, 4, 6, 6.5}));
  EXPECT_EQ(mesh.columns, 6);
  EXPECT_EQ(mesh.rows, 5);
  EXPECT_EQ(mesh.triangleCount(), size_t(2 * 5 * 4));
  EXPECT_EQ(mesh.droppedTriangles, 0u);
  EXPECT_TRUE(mesh.points.empty());  // nothing dropped: no border inside the picture

  options.gridStep = 1;
  const vs::DepthMeshBuilder fine(camera, range8(100, 200), 10, 7, options);
  fine.build(vs::Plane(10, 7, 128), mesh);
  EXPECT_EQ(mesh.columns, 12);
  EXPECT_EQ(mesh.rows, 9);
  EXPECT_EQ(mesh.triangleCount(), size_t(2 * 11 * 8));
}

TEST(MeshDepth, VerticesAreTheBackProjectedPointsDepthType0) {
  const vs::Camera camera = skewedCamera({1.0e5, -2.0e5, 3.0e4}, 0.1, -0.2, 0.05);
  const vs::DepthRange range = range8(80, 240);
  std::mt19937 random(1);
  vs::Plane depth(16, 12);
  for (uint16_t& level : depth.samples) level = uint16_t(random() % 256);
  vs::MeshOptions options;
  options.discontinuityThreshold = 1.0;
  const vs::DepthMeshBuilder builder(camera, range, 16, 12, options);
  vs::DepthMesh mesh;
  builder.build(depth, mesh);
  EXPECT_EQ(mesh.droppedTriangles, 0u);  // threshold 1 keeps every triangle
  for (int r = 0; r < mesh.rows; ++r)
    for (int c = 0; c < mesh.columns; ++c) {
      const size_t i = size_t(r) * mesh.columns + c;
      ASSERT_TRUE(mesh.valid[i]);
      const double u = mesh.gridU[c], v = mesh.gridV[r];
      const int px = std::clamp(int(std::lround(u)), 0, 15), py = std::clamp(int(std::lround(v)), 0, 11);
      const double z = vs::levelToZ(depth.at(px, py), range);
      const float* vertex = &mesh.vertices[i * 4];
      EXPECT_EQ(vertex[2], 1.0f);  // a = 1 for DepthType 0
      EXPECT_EQ(vertex[0], float(u));
      EXPECT_EQ(vertex[1], float(v));
      // Relative to the camera: world points near 1e5 would hide float rounding of the vertex.
      const vs::Vec3 expected = camera.backProject(u, v, z) - camera.t;
      const vs::Vec3 got = vertexWorld(camera, vertex) - camera.t;
      EXPECT_NEAR(vs::norm(got - expected), 0.0, 1e-5 * z) << "vertex " << c << ", " << r;
    }
}

TEST(MeshDepth, DepthType1VerticesLieOnTheWorldPlane) {
  // World z coordinates as depth, negative values and a tilted camera, as in the butterfly arc config.
  const vs::Camera camera = skewedCamera({3.0, -1.0, 4.0}, 0.3, 2.9, 0.1);
  const vs::DepthRange range = range8(0.46, -2.42);
  vs::Plane depth(12, 10);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) depth.at(x, y) = uint16_t(20 * x + y);
  vs::MeshOptions options;
  options.depthType = vs::kDepthTypeWorld;
  options.discontinuityThreshold = 1.0;
  const vs::DepthMeshBuilder builder(camera, range, 12, 10, options);
  vs::DepthMesh mesh;
  builder.build(depth, mesh);
  int checked = 0;
  for (int r = 0; r < mesh.rows; ++r)
    for (int c = 0; c < mesh.columns; ++c) {
      const size_t i = size_t(r) * mesh.columns + c;
      const double u = mesh.gridU[c], v = mesh.gridV[r];
      const int px = std::clamp(int(std::lround(u)), 0, 11), py = std::clamp(int(std::lround(v)), 0, 9);
      const double worldZ = vs::levelToZ(depth.at(px, py), range);
      bool ok = false;
      const vs::Vec3 expected = vs::backProjectDepth(camera, u, v, worldZ, vs::kDepthTypeWorld, ok);
      ASSERT_EQ(bool(mesh.valid[i]), ok) << "vertex " << c << ", " << r;
      if (!ok) continue;
      const vs::Vec3 got = vertexWorld(camera, &mesh.vertices[i * 4]);
      EXPECT_NEAR(got.z, worldZ, 1e-5 * (1 + std::fabs(worldZ)));
      EXPECT_NEAR(vs::norm(got - expected), 0.0, 1e-5 * (1 + vs::norm(expected - camera.t)));
      ++checked;
    }
  EXPECT_GT(checked, mesh.columns * mesh.rows / 2);
}

TEST(MeshDepth, InfiniteFarIsAHomogeneousPointAtInfinity) {
  const vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  vs::Plane depth(6, 5, 0);  // level 0: Zfar = inf
  const vs::DepthMeshBuilder builder(camera, range8(50, kInf), 6, 5, vs::MeshOptions{});
  vs::DepthMesh mesh;
  builder.build(depth, mesh);
  EXPECT_EQ(mesh.droppedTriangles, 0u);  // all at infinity: one surface
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    ASSERT_TRUE(mesh.valid[i]);
    EXPECT_EQ(mesh.vertices[i * 4 + 2], 1.0f);
    EXPECT_EQ(mesh.vertices[i * 4 + 3], 0.0f);
  }
  // Next to a finite depth a point at infinity is a discontinuity.
  depth.at(3, 2) = 255;
  builder.build(depth, mesh);
  EXPECT_GT(mesh.droppedTriangles, 0u);
}

TEST(MeshDepth, DiscontinuitiesDropTrianglesAndMarkTheirVertices) {
  const vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  const vs::DepthRange range = range8(100, 300);
  vs::Plane depth(8, 6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) depth.at(x, y) = x < 4 ? 250 : 20;  // a vertical depth step
  const double zNear = vs::levelToZ(250, range), zFar = vs::levelToZ(20, range);
  const double step = 1.0 - zNear / zFar;  // the relative depth difference across the step
  vs::MeshOptions options;
  options.discontinuityThreshold = step * 0.99;
  vs::DepthMesh mesh;
  vs::DepthMeshBuilder(camera, range, 8, 6, options).build(depth, mesh);
  // Grid columns -0.5, 0..7, 7.5: the quads between pixel columns 3 and 4 (one column of quads, 7
  // rows of quads) lose both triangles.
  EXPECT_EQ(mesh.droppedTriangles, size_t(2 * (mesh.rows - 1)));
  EXPECT_EQ(mesh.triangleCount(), size_t(2 * (mesh.rows - 1) * (mesh.columns - 2)));
  for (int r = 0; r < mesh.rows; ++r)
    for (int c = 0; c < mesh.columns; ++c) {
      const bool onStep = mesh.gridU[c] == 3 || mesh.gridU[c] == 4;
      EXPECT_EQ(mesh.boundary[size_t(r) * mesh.columns + c], onStep ? 1 : 0) << c << ", " << r;
    }
  EXPECT_EQ(mesh.points.size(), size_t(2 * mesh.rows));
  options.discontinuityThreshold = step * 1.01;
  vs::DepthMeshBuilder(camera, range, 8, 6, options).build(depth, mesh);
  EXPECT_EQ(mesh.droppedTriangles, 0u);
}

// A plane seen at a grazing angle: its levels rise by 20 a row (more than the threshold allows in
// relative depth near the far end) but evenly, so its triangles stay; the same rows with one uneven
// step (a second surface) lose the triangles across that step only.
TEST(MeshDepth, EvenlySteppingLevelsAreOnePlaneWhateverTheRelativeStep) {
  const vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  const vs::DepthRange range = range8(100, 10000);
  vs::Plane depth(6, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 6; ++x) depth.at(x, y) = uint16_t(10 + 20 * y + (y % 2));  // rounding: +-1
  vs::MeshOptions options;
  options.discontinuityThreshold = 0.05;
  ASSERT_GT(1.0 - vs::levelToZ(31, range) / vs::levelToZ(10, range), 0.05);  // relative steps too large
  vs::DepthMesh mesh;
  vs::DepthMeshBuilder(camera, range, 6, 8, options).build(depth, mesh);
  EXPECT_EQ(mesh.droppedTriangles, 0u);
  EXPECT_TRUE(mesh.points.empty());

  for (int y = 4; y < 8; ++y)
    for (int x = 0; x < 6; ++x) depth.at(x, y) = uint16_t(depth.at(x, y) + 30);  // a step between rows 3 and 4
  vs::DepthMeshBuilder(camera, range, 6, 8, options).build(depth, mesh);
  // Grid rows -0.5, 0..7, 7.5: only the row of quads between pixel rows 3 and 4 (grid rows 4, 5) loses
  // its triangles, 2 per quad, 7 quads.
  EXPECT_EQ(mesh.droppedTriangles, size_t(2 * (mesh.columns - 1)));
  for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const uint32_t rowsOf[3] = {mesh.triangles[t] / uint32_t(mesh.columns), mesh.triangles[t + 1] / uint32_t(mesh.columns),
                                mesh.triangles[t + 2] / uint32_t(mesh.columns)};
    const uint32_t top = std::min({rowsOf[0], rowsOf[1], rowsOf[2]});
    EXPECT_NE(top, 4u) << "triangle " << t / 3 << " spans the step";
  }
  // DepthType 1 levels are not affine on a plane: the rule is off, the grazing rows are dropped.
  options.depthType = vs::kDepthTypeWorld;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 6; ++x) depth.at(x, y) = uint16_t(10 + 20 * y + (y % 2));
  vs::DepthMeshBuilder(camera, range, 6, 8, options).build(depth, mesh);
  EXPECT_GT(mesh.droppedTriangles, 0u);
}

// A vertex left without a kept triangle is drawn as a point, unless every valid neighbour is nearer
// (a speck of background seen through the depth map).
TEST(MeshDepth, OrphanVerticesAreDrawnAsPointsUnlessBehindAllAround) {
  const vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  const vs::DepthRange range = range8(100, 300);
  vs::MeshOptions options;
  options.discontinuityThreshold = 0.01;
  auto gridIndex = [](const vs::DepthMesh& mesh, int x, int y) { return uint32_t((y + 1) * mesh.columns + x + 1); };
  auto drawnAsPoint = [](const vs::DepthMesh& mesh, uint32_t i) {
    return std::find(mesh.points.begin(), mesh.points.end(), i) != mesh.points.end();
  };
  vs::Plane depth(9, 9, 100);
  depth.at(2, 2) = 250;  // nearer than all around: a thin foreground sample
  depth.at(6, 6) = 10;   // farther than all around
  for (int x = 0; x < 9; ++x) depth.at(x, 4) = uint16_t(x == 4 ? 175 : 100);  // between a near and a far neighbour
  depth.at(4, 3) = 250;
  vs::DepthMesh mesh;
  vs::DepthMeshBuilder(camera, range, 9, 9, options).build(depth, mesh);
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (uint32_t orphan : {gridIndex(mesh, 2, 2), gridIndex(mesh, 6, 6), gridIndex(mesh, 4, 4)})
      ASSERT_NE(mesh.triangles[t], orphan);
  EXPECT_TRUE(drawnAsPoint(mesh, gridIndex(mesh, 2, 2)));
  EXPECT_TRUE(drawnAsPoint(mesh, gridIndex(mesh, 4, 4)));
  EXPECT_FALSE(drawnAsPoint(mesh, gridIndex(mesh, 6, 6)));
}

// Code that builds meshes without a config (tests, tools) gets MeshRender's own default threshold.
TEST(MeshDepth, DefaultThresholdIsTheOptionTables) {
  const vs::OptionTable table = vs::meshRenderOptionTable();
  const vs::OptionSpec* spec = table.find("MeshDiscontinuityThreshold");
  ASSERT_NE(spec, nullptr);
  EXPECT_EQ(vs::MeshOptions{}.discontinuityThreshold, std::stod(spec->defaultValue));
}

TEST(MeshDepth, MissingDepthLevelDropsItsVertices) {
  const vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  vs::Plane depth(8, 6, 100);
  depth.at(5, 3) = 0;
  vs::MeshOptions options;
  options.missingDepthLevel = 0;
  vs::DepthMesh mesh;
  vs::DepthMeshBuilder(camera, range8(100, 300), 8, 6, options).build(depth, mesh);
  // Grid vertex of pixel (5, 3) is column 6, row 4 (after the half-pixel border).
  const size_t missing = size_t(4) * mesh.columns + 6;
  EXPECT_FALSE(mesh.valid[missing]);
  for (uint32_t index : mesh.triangles) EXPECT_NE(index, missing);
  // Its 4 quads keep one triangle each (the diagonal that avoids it).
  EXPECT_EQ(mesh.droppedTriangles, 4u);
  EXPECT_EQ(mesh.triangleCount(), size_t(2 * (mesh.rows - 1) * (mesh.columns - 1) - 4));
}

// The clip matrix, applied in double the way OpenGL applies it (clip coordinates, perspective divide,
// viewport), puts every vertex where the pinhole model does: projection and pixel-centre conventions.
TEST(MeshProjection, ClipMatrixPutsVerticesWhereThePinholeModelDoes) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const vs::Vec3 farAway(2.5e6, -1.2e6, 7.0e5);  // large common world offset
  for (int trial = 0; trial < 20; ++trial) {
    const vs::Camera reference = skewedCameraNear(farAway, random);
    vs::Camera virtualCamera = skewedCameraNear(farAway, random);
    virtualCamera.K[0][1] = -2.0;
    const vs::RenderGrid grid = vs::lumaGrid(virtualCamera, 160, 120);
    const vs::Mat4 clip = vs::meshClipMatrix(reference, virtualCamera, grid, {0.001, 0.05});
    for (int k = 0; k < 50; ++k) {
      const double u = 80 + 70 * unit(random), v = 60 + 55 * unit(random), z = 60 + 40 * unit(random);
      double vertex[4], inverseCameraZ;
      ASSERT_TRUE(vs::referenceVertex(reference, 0, u, v, 1.0 / z, vertex, inverseCameraZ));
      double x, y, q;
      ASSERT_TRUE(vs::clipToPixel(clip, grid, vertex, x, y, q));
      // The pinhole model, relative to the reference camera so the offset cancels here too.
      const vs::RelativePose pose = vs::relativePose(reference, virtualCamera);
      const vs::Vec3 xv = pose.apply(reference.pixelToCamera(u, v, z));
      double ex, ey;
      ASSERT_TRUE(virtualCamera.cameraToPixel(xv, ex, ey));
      EXPECT_NEAR(x, ex, 1e-7);
      EXPECT_NEAR(y, ey, 1e-7);
      EXPECT_NEAR(q, 1.0 / xv.z, 1e-12);
    }
  }
}

// pinholeReferenceShift against the geometry itself: the virtual pixel that shows reference pixel
// (u, v) at depth 1/q meets the surface facing the reference camera at depth 1/(q + dq) (camera z
// constant) at a reference position found by intersecting that pixel's ray with the plane in world
// space; (du, dv) is minus its rate of change with dq (central difference).
TEST(MeshProjection, ReferenceShiftIsWhereTheVirtualPixelMeetsTheMovedSurface) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const vs::Vec3 farAway(2.5e6, -1.2e6, 7.0e5);
  for (int trial = 0; trial < 20; ++trial) {
    const vs::Camera reference = skewedCameraNear(farAway, random);
    vs::Camera virtualCamera = skewedCameraNear(farAway, random);
    virtualCamera.K[0][0] = 430.0;  // another focal length: the shift is not the virtual displacement
    const vs::RenderGrid grid = vs::lumaGrid(virtualCamera, 160, 120);
    const vs::ReferenceShift shift = vs::pinholeReferenceShift(reference, virtualCamera, grid);
    for (int k = 0; k < 20; ++k) {
      const double u = 80 + 70 * unit(random), v = 60 + 55 * unit(random), z = 60 + 40 * unit(random);
      double x, y, zv;
      ASSERT_TRUE(virtualCamera.project(reference.backProject(u, v, z), x, y, zv));
      // The reference position where virtual pixel (x, y)'s ray meets the plane of reference camera depth
      // zPlane (relative to the virtual centre, so the world offset cancels).
      auto metAt = [&](double zPlane, double& ur, double& vr) {
        const vs::Vec3 ray = virtualCamera.rayDirectionWorld(x, y);
        const vs::Vec3 centreInReference = reference.worldToCamera(virtualCamera.centre());
        const vs::Vec3 rayInReference = reference.R * ray;
        const double along = (zPlane - centreInReference.z) / rayInReference.z;
        const vs::Vec3 point = centreInReference + rayInReference * along;
        ASSERT_TRUE(reference.cameraToPixel(point, ur, vr));
      };
      const double q = 1.0 / z, dq = 1e-4 * q;
      double ua, va, ub, vb;
      metAt(1.0 / (q + dq), ua, va);
      metAt(1.0 / (q - dq), ub, vb);
      const double expectedU = -(ua - ub) / (2.0 * dq), expectedV = -(va - vb) / (2.0 * dq);
      double du = 0.0, dv = 0.0;
      ASSERT_TRUE(shift(u, v, q, du, dv));
      const double scale = std::hypot(expectedU, expectedV);
      EXPECT_GT(scale, 0.0);
      EXPECT_NEAR(du, expectedU, 1e-5 * scale) << "trial " << trial;
      EXPECT_NEAR(dv, expectedV, 1e-5 * scale) << "trial " << trial;
    }
  }
}

// pinholeDisplacementRate against the geometry: how far the virtual pixel of reference pixel (u, v)
// moves per unit of inverse depth q, from the point's projections at q - dq and q + dq (central
// difference); infinite where the point is behind the virtual camera.
TEST(MeshProjection, DisplacementRateIsHowFarTheVirtualPixelMovesPerUnitOfInverseDepth) {
  std::mt19937 random(12);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const vs::Vec3 farAway(2.5e6, -1.2e6, 7.0e5);
  for (int trial = 0; trial < 20; ++trial) {
    const vs::Camera reference = skewedCameraNear(farAway, random);
    vs::Camera virtualCamera = skewedCameraNear(farAway, random);
    virtualCamera.K[0][0] = 430.0;
    const vs::RenderGrid grid = vs::lumaGrid(virtualCamera, 160, 120);
    const vs::DisplacementRate rate = vs::pinholeDisplacementRate(reference, virtualCamera, grid);
    ASSERT_TRUE(rate);
    for (int k = 0; k < 20; ++k) {
      const double u = 80 + 70 * unit(random), v = 60 + 55 * unit(random), z = 60 + 40 * unit(random);
      const double q = 1.0 / z, dq = 1e-4 * q;
      double xa, ya, xb, yb, zv;
      ASSERT_TRUE(virtualCamera.project(reference.backProject(u, v, 1.0 / (q + dq)), xa, ya, zv));
      ASSERT_TRUE(virtualCamera.project(reference.backProject(u, v, 1.0 / (q - dq)), xb, yb, zv));
      const double expected = std::hypot(xa - xb, ya - yb) / (2.0 * dq);
      EXPECT_GT(expected, 0.0);
      EXPECT_NEAR(rate(u, v, q), expected, 1e-5 * expected) << "trial " << trial;
    }
    // A point behind the virtual camera (a reference at its centre looking the other way): no finite rate.
    const vs::Camera behind = skewedCamera(virtualCamera.t, 0.0, std::acos(-1.0), 0.0);
    double x = 0.0, y = 0.0, zv = 0.0;
    virtualCamera.project(behind.backProject(80.0, 60.0, 50.0), x, y, zv);
    ASSERT_LT(zv, 0.0);
    const vs::DisplacementRate away = vs::pinholeDisplacementRate(behind, virtualCamera, grid);
    EXPECT_FALSE(away(80.0, 60.0, 1.0 / 50.0) < std::numeric_limits<double>::infinity()) << "trial " << trial;
  }
}

TEST(MeshProjection, PixelCentresAndDepthPlanesMapToTheirNdc) {
  vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  const vs::RenderGrid grid = vs::lumaGrid(camera, 100, 80);
  const vs::Mat4 p = vs::projectionMatrix(grid, {0.01, 0.02});
  // Point on pixel (u, v) at depth z: x_cam = K^-1 (u, v, 1) z.
  auto ndc = [&](double u, double v, double z, double out[3]) {
    const vs::Vec3 xc = camera.pixelToCamera(u, v, z);
    double c[4];
    for (int r = 0; r < 4; ++r) c[r] = p.m[r][0] * xc.x + p.m[r][1] * xc.y + p.m[r][2] * xc.z + p.m[r][3];
    for (int k = 0; k < 3; ++k) out[k] = c[k] / c[3];
  };
  double n[3];
  ndc(0, 0, 100, n);  // top-left pixel centre, far plane
  EXPECT_NEAR(n[0], 2 * 0.5 / 100 - 1, 1e-12);
  EXPECT_NEAR(n[1], 2 * 0.5 / 80 - 1, 1e-12);
  EXPECT_NEAR(n[2], 1.0, 1e-12);
  ndc(99, 79, 50, n);  // bottom-right pixel centre, near plane
  EXPECT_NEAR(n[0], 2 * 99.5 / 100 - 1, 1e-12);
  EXPECT_NEAR(n[1], 2 * 79.5 / 80 - 1, 1e-12);
  EXPECT_NEAR(n[2], -1.0, 1e-12);
}

TEST(MeshProjection, ChromaGridPutsChromaSamplesAtTheCentresOfTheirLumaBlocks) {
  const vs::Camera camera = skewedCamera({0, 0, 0}, 0, 0, 0);
  const vs::RenderGrid luma = vs::lumaGrid(camera, 100, 80);
  const vs::RenderGrid chroma = vs::chromaGrid(camera, 100, 80, vs::ChromaFormat::Yuv420);
  EXPECT_EQ(chroma.width, 50);
  EXPECT_EQ(chroma.height, 40);
  const vs::Vec3 xc(3.0, -2.0, 40.0);
  const vs::Vec3 lumaPixel = luma.K * xc, chromaPixel = chroma.K * xc;
  const double lu = lumaPixel.x / lumaPixel.z, lv = lumaPixel.y / lumaPixel.z;
  const double cu = chromaPixel.x / chromaPixel.z, cv = chromaPixel.y / chromaPixel.z;
  EXPECT_NEAR(2 * cu + 0.5, lu, 1e-12);
  EXPECT_NEAR(2 * cv + 0.5, lv, 1e-12);
  const vs::RenderGrid full = vs::chromaGrid(camera, 100, 80, vs::ChromaFormat::Yuv444);
  EXPECT_EQ(full.width, 100);
  EXPECT_TRUE(full.K == camera.K);
}

TEST(MeshProjection, SceneDepthRangeBoundsEveryVertex) {
  const vs::Camera reference = skewedCamera({0, 0, 0}, 0, 0, 0);
  const vs::Camera virtualCamera = skewedCamera({12, -3, 5}, 0.02, -0.05, 0.01);
  for (int depthType : {0, 1}) {
    for (double zfar : {240.0, kInf}) {
      const vs::DepthRange range = range8(80, zfar);
      vs::InverseDepthRange bounds;
      ASSERT_TRUE(vs::sceneInverseDepthRange(reference, range, depthType, 160, 120, virtualCamera, bounds));
      std::mt19937 random(3);
      vs::Plane depth(160, 120);
      for (uint16_t& level : depth.samples) level = uint16_t(random() % 256);
      depth.at(0, 0) = 0;
      depth.at(159, 119) = 255;
      vs::MeshOptions options;
      options.depthType = depthType;
      vs::DepthMesh mesh;
      vs::DepthMeshBuilder(reference, range, 160, 120, options).build(depth, mesh);
      const vs::InverseDepthRange used = vs::meshInverseDepthRange(mesh, reference, virtualCamera);
      EXPECT_GE(used.lo, bounds.lo - 1e-12) << "DepthType " << depthType << ", Zfar " << zfar;
      EXPECT_LE(used.hi, bounds.hi + 1e-12) << "DepthType " << depthType << ", Zfar " << zfar;
      const vs::InverseDepthRange planes = vs::clipPlanes(bounds);
      EXPECT_LT(planes.lo, bounds.lo);
      EXPECT_GT(planes.hi, bounds.hi);
    }
  }
  // A virtual camera looking sideways sees part of the depth range behind it: no bound.
  const vs::Camera sideways = skewedCamera({0, 0, 150}, 0, 1.5, 0);
  vs::InverseDepthRange bounds;
  EXPECT_FALSE(vs::sceneInverseDepthRange(reference, range8(80, 240), 0, 160, 120, sideways, bounds));
}

// Reads back what writeMeshPly wrote: header lines, then the binary vertices and faces.
struct PlyData {
  std::vector<std::string> header;
  std::vector<float> xyz;
  std::vector<uint8_t> rgb;
  std::vector<int32_t> faces;
};

PlyData readPly(const std::filesystem::path& path) {
  PlyData ply;
  std::ifstream file(path, std::ios::binary);
  std::string line;
  size_t vertices = 0, faces = 0;
  while (std::getline(file, line)) {
    ply.header.push_back(line);
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
    if (line.rfind("element face ", 0) == 0) faces = std::stoul(line.substr(13));
    if (line == "end_header") break;
  }
  for (size_t i = 0; i < vertices; ++i) {
    float v[3];
    uint8_t c[3];
    file.read(reinterpret_cast<char*>(v), sizeof v);  // little-endian host
    file.read(reinterpret_cast<char*>(c), sizeof c);
    ply.xyz.insert(ply.xyz.end(), v, v + 3);
    ply.rgb.insert(ply.rgb.end(), c, c + 3);
  }
  for (size_t i = 0; i < faces; ++i) {
    uint8_t count = 0;
    int32_t index[3];
    file.read(reinterpret_cast<char*>(&count), 1);
    EXPECT_EQ(count, 3);
    file.read(reinterpret_cast<char*>(index), sizeof index);
    ply.faces.insert(ply.faces.end(), index, index + 3);
  }
  EXPECT_TRUE(file.good());
  EXPECT_EQ(file.peek(), std::char_traits<char>::eof());
  return ply;
}

TEST(MeshPly, WritesTheMeshInWorldCoordinatesWithColour) {
  const vs::Camera camera = skewedCamera({100, 200, -50}, 0.1, 0.2, 0.0);
  vs::Plane depth(6, 4, 200);
  depth.at(2, 1) = 0;  // level 0 at Zfar = inf: left out of the file with its triangles
  vs::Frame texture(vs::FrameFormat{6, 4, 8, vs::ChromaFormat::Yuv420});
  texture.fill(0);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) texture.planes[0].at(x, y) = uint16_t(40 * x + 10 * y);
  vs::MeshOptions options;
  options.discontinuityThreshold = 1.0;
  vs::DepthMesh mesh;
  vs::DepthMeshBuilder(camera, range8(100, kInf), 6, 4, options).build(depth, mesh);
  const std::filesystem::path dir = vs::test::scratchDir("mesh_ply");
  const std::string path = vs::plyPathForView((dir / "mesh.ply").string(), "Left");
  EXPECT_EQ(path, (dir / "mesh_left.ply").string());
  vs::writeMeshPly(path, mesh, camera, texture);

  const PlyData ply = readPly(path);
  ASSERT_GE(ply.header.size(), 3u);
  EXPECT_EQ(ply.header[0], "ply");
  EXPECT_EQ(ply.header[1], "format binary_little_endian 1.0");
  // Every vertex but the one at infinity (grid column 3, row 2), and the triangles without it.
  EXPECT_EQ(ply.xyz.size(), 3 * (mesh.vertexCount() - 1));
  size_t kept = 0;
  const uint32_t infinite = uint32_t(2 * mesh.columns + 3);
  for (size_t t = 0; t < mesh.triangles.size(); t += 3)
    kept += mesh.triangles[t] != infinite && mesh.triangles[t + 1] != infinite && mesh.triangles[t + 2] != infinite;
  EXPECT_EQ(ply.faces.size(), 3 * kept);
  for (int32_t index : ply.faces) EXPECT_LT(size_t(index), ply.xyz.size() / 3);
  // First vertex: grid (-0.5, -0.5), pixel (0, 0), depth level 200. Grey texture (U = V = 128).
  const vs::Vec3 first = camera.backProject(-0.5, -0.5, vs::levelToZ(200, range8(100, kInf)));
  EXPECT_NEAR(ply.xyz[0], first.x, 1e-3);
  EXPECT_NEAR(ply.xyz[1], first.y, 1e-3);
  EXPECT_NEAR(ply.xyz[2], first.z, 1e-3);
  EXPECT_EQ(ply.rgb[0], 0);
  const size_t lastVertex = ply.xyz.size() / 3 - 1;  // grid (5.5, 3.5) -> pixel (5, 3): 40*5 + 30
  EXPECT_EQ(ply.rgb[3 * lastVertex], 230);
  EXPECT_EQ(ply.rgb[3 * lastVertex + 1], 230);
  EXPECT_EQ(ply.rgb[3 * lastVertex + 2], 230);

  EXPECT_EQ(vs::plyPathForView("out/mesh", "Right"), "out/mesh_right.ply");
  EXPECT_EQ(vs::plyPathForView("out.d/mesh.PLY", "Right"), "out.d/mesh_right.PLY");
  EXPECT_THROW(vs::writeMeshPly((dir / "missing" / "x.ply").string(), mesh, camera, texture), vs::InputError);
}

}  // namespace
