// The adaptive mesh (MeshMaxError, DepthMesh.h) without OpenGL, against the full grid built from the same
// depth map: it covers exactly the same area, has no T-junction (so no crack), keeps every depth sample
// within the bound (with a texture, also within the colour bound: the displacement along the reference
// shift times the luma step on the side it goes), and merges planes. Truth: the full grid's triangles,
// the depth samples and the texture.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "Common/Camera.h"
#include "Common/Depth.h"
#include "Common/Frame.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/MeshProjection.h"

namespace {

constexpr int kWidth = 96, kHeight = 80;

vs::Camera camera() {
  vs::Camera c;
  c.name = "test";
  c.K[0][0] = 400.0, c.K[0][2] = 47.5;
  c.K[1][1] = 400.0, c.K[1][2] = 39.5;
  return c;
}

vs::DepthRange range8() {
  vs::DepthRange range;
  range.znear = 100.0;
  range.zfar = 200.0;
  range.bitDepth = 8;
  return range;
}

// A tilted plane (levels affine in the image), a raised flat box (a depth step all around it) and a
// paraboloid bump (curved): planes to merge, edges to keep, curvature to bound.
vs::Plane depthMap() {
  vs::Plane depth(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      double level = 40.0 + 0.37 * x + 0.21 * y;
      if (x >= 10 && x < 34 && y >= 12 && y < 40) level = 200.0;
      const double dx = x - 66.0, dy = y - 52.0;
      if (dx * dx + dy * dy < 18.0 * 18.0) level += 40.0 - 40.0 * (dx * dx + dy * dy) / (18.0 * 18.0);
      depth.at(x, y) = uint16_t(std::lround(level));
    }
  return depth;
}

// Levels constant along the rows and zigzagging by 2 levels from row to row: no aligned block of 2 x 2
// cells or more is planar within a quarter of a level, but every row of cells is (it is one plane),
// so at small bounds only 2:1 rectangles of cells side by side merge.
vs::Plane zigzag() {
  vs::Plane depth(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) depth.at(x, y) = uint16_t(100 + 2 * (y % 2));
  return depth;
}

// One depth level moves a point by about a quarter of a virtual-camera pixel (as on Middlebury's view 3).
constexpr double kRate = 0.25 / ((1.0 / 100.0 - 1.0 / 200.0) / 255.0);

double uOf(const vs::DepthMesh& mesh, uint32_t i) { return double(mesh.vertices[i * 4]) / double(mesh.vertices[i * 4 + 2]); }
double vOf(const vs::DepthMesh& mesh, uint32_t i) { return double(mesh.vertices[i * 4 + 1]) / double(mesh.vertices[i * 4 + 2]); }
double qOf(const vs::DepthMesh& mesh, uint32_t i) { return double(mesh.vertices[i * 4 + 3]) / double(mesh.vertices[i * 4 + 2]); }

double area(const vs::DepthMesh& mesh, uint32_t a, uint32_t b, uint32_t c) {
  return 0.5 * std::fabs((uOf(mesh, b) - uOf(mesh, a)) * (vOf(mesh, c) - vOf(mesh, a)) -
                         (uOf(mesh, c) - uOf(mesh, a)) * (vOf(mesh, b) - vOf(mesh, a)));
}

double totalArea(const vs::DepthMesh& mesh) {
  double sum = 0.0;
  for (size_t t = 0; t < mesh.triangleCount(); ++t)
    sum += area(mesh, mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]);
  return sum;
}

// A texture with sharp vertical stripes on the right half and flat grey on the left.
vs::Plane stripes() {
  vs::Plane luma(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) luma.at(x, y) = uint16_t(x < kWidth / 2 ? 128 : (x / 3) % 2 ? 200 : 40);
  return luma;
}

// The texture at (x, y), bilinear between samples, clamped to the picture.
double lumaAt(const vs::Plane& luma, double x, double y) {
  x = std::clamp(x, 0.0, double(kWidth - 1));
  y = std::clamp(y, 0.0, double(kHeight - 1));
  const int i = std::min(int(std::floor(x)), kWidth - 2), j = std::min(int(std::floor(y)), kHeight - 2);
  const double fx = x - i, fy = y - j;
  return (1 - fy) * ((1 - fx) * luma.at(i, j) + fx * luma.at(i + 1, j)) +
         fy * ((1 - fx) * luma.at(i, j + 1) + fx * luma.at(i + 1, j + 1));
}

// Reference shifts (ReferenceShift, DepthMesh.h) in reference pixels per unit of q: one depth level
// moves the texture by a quarter of a pixel, along a row (as between rectified cameras), diagonally, or
// along the columns (along the stripes, which then never change colour).
struct Shift {
  double du, dv;
};
constexpr double kLevel = (1.0 / 100.0 - 1.0 / 200.0) / 255.0;
constexpr Shift kAlongRows{-0.25 / kLevel, 0.0}, kDiagonal{0.15 / kLevel, -0.2 / kLevel}, kAlongColumns{0.0, 0.25 / kLevel};

void build(double maxError, bool adaptive, vs::DepthMesh& mesh, double maxColourError = 0.0, const vs::Plane* luma = nullptr,
           Shift shift = kAlongRows, const vs::Plane& depth = depthMap()) {
  vs::MeshOptions options;
  options.maxError = maxError;
  options.maxColourError = maxColourError;
  const vs::DisplacementRate rate = [](double, double, double) { return kRate; };
  const vs::ReferenceShift referenceShift = [shift](double, double, double, double& du, double& dv) {
    du = shift.du;
    dv = shift.dv;
    return true;
  };
  const vs::DepthMeshBuilder builder(camera(), range8(), kWidth, kHeight, options,
                                     adaptive ? rate : vs::DisplacementRate{}, referenceShift);
  builder.build(depth, mesh, luma);
}

TEST(MeshAdaptive, SameAreaNoTJunctionAndEverySampleWithinTheBound) {
  const vs::Plane luma = stripes();
  const vs::Plane scene = depthMap(), rows = zigzag();
  const struct {
    double maxError, maxColourError;
    Shift shift;
    const vs::Plane* depth;
  } cases[] = {{0.0, 0.0, kAlongRows, &scene}, {0.1, 0.0, kAlongRows, &scene}, {0.5, 0.0, kAlongRows, &scene},
               {2.0, 0.0, kAlongRows, &scene}, {2.0, 4.0, kAlongRows, &scene},  {2.0, 2.6, kAlongRows, &scene},
               {2.0, 4.0, kDiagonal, &scene},  {0.1, 0.0, kAlongRows, &rows}};
  for (const auto& bounds : cases) {
    const double maxError = bounds.maxError, maxColourError = bounds.maxColourError;
    const Shift shift = bounds.shift;
    vs::DepthMesh grid, mesh;
    build(0.1, false, grid, 0.0, nullptr, kAlongRows, *bounds.depth);
    build(maxError, true, mesh, maxColourError, maxColourError > 0.0 ? &luma : nullptr, shift, *bounds.depth);
    EXPECT_EQ(mesh.gridTriangles, grid.triangleCount());
    EXPECT_LT(mesh.triangleCount(), grid.triangleCount() / (maxError >= 0.5 && maxColourError == 0.0 ? 3 : 1))
        << "MeshMaxError " << maxError;
    // The zigzag merges only as 2:1 rectangles of two cells, stacked in columns two cells wide whose
    // inner vertices no leaf uses: about half the grid's triangles.
    if (bounds.depth == &rows) {
      EXPECT_LT(double(mesh.triangleCount()), 0.55 * double(grid.triangleCount()));
    }
    // The same points and outline as the full grid.
    EXPECT_EQ(mesh.points, grid.points);
    EXPECT_EQ(mesh.farthestOrphans, grid.farthestOrphans);
    EXPECT_NEAR(totalArea(mesh), totalArea(grid), 1e-6 * totalArea(grid)) << "MeshMaxError " << maxError;

    // No vertex of the mesh lies inside a horizontal or vertical triangle side: no T-junction.
    std::set<uint32_t> used(mesh.triangles.begin(), mesh.triangles.end());
    const uint32_t columns = uint32_t(mesh.columns);
    size_t junctions = 0;
    for (size_t t = 0; t < mesh.triangleCount(); ++t)
      for (int e = 0; e < 3; ++e) {
        uint32_t a = mesh.triangles[3 * t + e], b = mesh.triangles[3 * t + (e + 1) % 3];
        if (a > b) std::swap(a, b);
        if (a / columns == b / columns) {
          for (uint32_t i = a + 1; i < b; ++i) junctions += used.count(i);
        } else if (a % columns == b % columns) {
          for (uint32_t i = a + columns; i < b; i += columns) junctions += used.count(i);
        }
      }
    EXPECT_EQ(junctions, size_t(0)) << "MeshMaxError " << maxError;

    // Every vertex of a kept grid triangle lies, on the mesh, within the bound of its own depth: the
    // inverse depth interpolated at its position in the triangles that contain it, times the rate.
    std::vector<uint8_t> inGrid(grid.vertexCount(), 0);
    for (uint32_t i : grid.triangles) inGrid[i] = 1;
    // The vertices hold q (<= 1/100 here) in float: the interpolated q is exact to a few of its ulps,
    // each 1.2e-5 px at this rate, whatever the triangles (the old 1e-6 px held only by luck of the fan).
    const double floatSlack = 4.0 * double(std::numeric_limits<float>::epsilon()) * 0.01 * kRate;
    double worst = 0.0;
    size_t checked = 0;
    for (uint32_t i = 0; i < uint32_t(grid.vertexCount()); ++i) {
      if (!inGrid[i]) continue;
      const double u = uOf(grid, i), v = vOf(grid, i), q = qOf(grid, i);
      bool found = false;
      for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t a = mesh.triangles[3 * t], b = mesh.triangles[3 * t + 1], c = mesh.triangles[3 * t + 2];
        const double ua = uOf(mesh, a), va = vOf(mesh, a), ub = uOf(mesh, b), vb = vOf(mesh, b);
        const double uc = uOf(mesh, c), vc = vOf(mesh, c);
        if (std::max({ua, ub, uc}) < u || std::min({ua, ub, uc}) > u || std::max({va, vb, vc}) < v ||
            std::min({va, vb, vc}) > v)
          continue;
        const double d = (ub - ua) * (vc - va) - (uc - ua) * (vb - va);
        if (std::fabs(d) < 1e-12) continue;
        const double beta = ((u - ua) * (vc - va) - (uc - ua) * (v - va)) / d;
        const double gamma = ((ub - ua) * (v - va) - (u - ua) * (vb - va)) / d;
        if (beta < -1e-9 || gamma < -1e-9 || beta + gamma > 1.0 + 1e-9) continue;
        const double interpolated = (1.0 - beta - gamma) * qOf(mesh, a) + beta * qOf(mesh, b) + gamma * qOf(mesh, c);
        const double error = std::fabs(interpolated - q) * kRate;
        EXPECT_LE(error, maxError + floatSlack) << "vertex " << i << ", MeshMaxError " << maxError;
        if (maxColourError > 0.0) {
          // With the texture: the virtual pixel that truly shows this sample shows the texture
          // (interpolated - q) (du, dv) before it; its colour changes by the luma step one pixel back
          // along that shift times the shift's length, which must stay within the colour bound.
          const int x = std::clamp(int(std::lround(u)), 0, kWidth - 1), y = std::clamp(int(std::lround(v)), 0, kHeight - 1);
          const double signedError = interpolated - q, length = std::hypot(shift.du, shift.dv);
          const double back = signedError > 0.0 ? -1.0 : 1.0;
          const double step =
              std::fabs(lumaAt(luma, x + back * shift.du / length, y + back * shift.dv / length) - luma.at(x, y));
          EXPECT_LE(std::fabs(signedError) * length * step, maxColourError + floatSlack / kRate * length * step)
              << "vertex " << i << ", MeshMaxColourError " << maxColourError;
        }
        worst = std::max(worst, error);
        found = true;
      }
      EXPECT_TRUE(found) << "vertex " << i << " is not on the adaptive mesh";
      ++checked;
    }
    EXPECT_GT(checked, size_t(kWidth * kHeight / 2));
    std::printf("%s, MeshMaxError %.2f, MeshMaxColourError %.1f: %zu triangles (grid %zu), largest sample displacement %.4f px\n",
                bounds.depth == &rows ? "zigzag" : "scene", maxError, maxColourError, mesh.triangleCount(), grid.triangleCount(), worst);
  }
}

// The colour bound measures the luma change along the reference shift only: stripes along the columns,
// shifted along the columns, never change colour, so the mesh is the one without a colour bound; shifted
// along the rows, they keep more triangles.
TEST(MeshAdaptive, ColourBoundCountsOnlyTheStepAlongTheShift) {
  const vs::Plane luma = stripes();
  vs::DepthMesh plain, along, across;
  build(2.0, true, plain);
  build(2.0, true, along, 2.6, &luma, kAlongColumns);
  build(2.0, true, across, 2.6, &luma, kAlongRows);
  EXPECT_EQ(along.triangles, plain.triangles);
  EXPECT_GT(across.triangleCount(), plain.triangleCount());
}

// A larger bound merges more (the flat top of the box merges even at 0).
TEST(MeshAdaptive, LargerBoundsMergeMore) {
  size_t previous = SIZE_MAX;
  for (double maxError : {0.0, 0.05, 0.25, 1.0}) {
    vs::DepthMesh mesh;
    build(maxError, true, mesh);
    EXPECT_LE(mesh.triangleCount(), previous) << "MeshMaxError " << maxError;
    previous = mesh.triangleCount();
  }
}

// Rectified cameras (the same rotation and focal length, the centre moved along the rows, another
// principal point): the pinhole shift and rate are the same at every (u, v, q), to the bit, so the builder
// computes them once (ReferenceShift::uniform, DisplacementRate::uniform). Truth: the formula evaluated at
// each point, and the mesh built through the same terms wrapped in a function, which the builder calls at
// every vertex and block corner. A rotated virtual camera is not uniform and builds the same way too.
TEST(MeshAdaptive, PinholeTermsComputedOnceGiveTheMeshOfTermsComputedAtEveryVertex) {
  const vs::Camera reference = camera();
  vs::Camera rectified = camera();
  rectified.t.x = 3.0;
  rectified.K[0][2] = 51.25;
  vs::Camera rotated = rectified;
  const double angle = 0.03;
  rotated.R[0][0] = rotated.R[2][2] = std::cos(angle);
  rotated.R[0][2] = std::sin(angle);
  rotated.R[2][0] = -std::sin(angle);
  // A texture with steps of every size up to 255 and, at 16 bits, beyond the builder's table of steps.
  vs::Plane luma(kWidth, kHeight), deepLuma(kWidth, kHeight);
  std::mt19937 random(7);
  for (uint16_t& sample : luma.samples) sample = uint16_t(random() % 256);
  for (uint16_t& sample : deepLuma.samples) sample = uint16_t(random() % 4096);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const vs::Camera* virtualCamera : {&rectified, &rotated}) {
    const vs::RenderGrid grid = vs::lumaGrid(*virtualCamera, kWidth, kHeight);
    const vs::DisplacementRate rate = vs::pinholeDisplacementRate(reference, *virtualCamera, grid);
    const vs::ReferenceShift shift = vs::pinholeReferenceShift(reference, *virtualCamera, grid);
    double rateLimit = 0.0, shiftLimit = 0.0;
    const bool uniform = virtualCamera == &rectified;
    ASSERT_EQ(rate.uniform(rateLimit), uniform);
    ASSERT_EQ(shift.uniform(shiftLimit), uniform);
    if (uniform) {
      ASSERT_GT(rateLimit, 1.0);
      ASSERT_GT(shiftLimit, 1.0);
      double du0 = 0.0, dv0 = 0.0;
      ASSERT_TRUE(shift(0.0, 0.0, 0.0, du0, dv0));
      const double rate0 = rate(0.0, 0.0, 0.0);
      for (int k = 0; k < 200; ++k) {
        const double u = -0.5 + kWidth * unit(random), v = -0.5 + kHeight * unit(random), q = 0.02 * unit(random);
        double du = 0.0, dv = 0.0;
        ASSERT_TRUE(shift(u, v, q, du, dv));
        EXPECT_EQ(du, du0);
        EXPECT_EQ(dv, dv0);
        EXPECT_EQ(rate(u, v, q), rate0);
      }
    }
    const vs::DisplacementRate rateEveryVertex = [rate](double u, double v, double q) { return rate(u, v, q); };
    const vs::ReferenceShift shiftEveryVertex = [shift](double u, double v, double q, double& du, double& dv) {
      return shift(u, v, q, du, dv);
    };
    double limit = 0.0;
    ASSERT_FALSE(rateEveryVertex.uniform(limit));
    ASSERT_FALSE(shiftEveryVertex.uniform(limit));
    vs::MeshOptions options;
    options.maxError = 0.5;
    const vs::Plane* textures[3] = {&luma, &deepLuma, nullptr};
    for (const vs::Plane* texture : textures) {
      const vs::DepthMeshBuilder once(reference, range8(), kWidth, kHeight, options, rate, shift);
      const vs::DepthMeshBuilder everywhere(reference, range8(), kWidth, kHeight, options, rateEveryVertex, shiftEveryVertex);
      vs::DepthMesh a, b;
      once.build(depthMap(), a, texture);
      everywhere.build(depthMap(), b, texture);
      EXPECT_EQ(a.triangles, b.triangles);
      EXPECT_EQ(a.points, b.points);
      EXPECT_LT(a.triangleCount(), a.gridTriangles) << "some blocks merge";
    }
  }
}

// largestFactorWithin: |e| rate <= bound exactly when |e| <= the threshold, for every double e, checked
// against the product itself near the threshold, far from it, for NaN and the infinities.
TEST(MeshAdaptive, LargestFactorWithinIsExactlyWhereTheProductPasses) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> exponent(-8.0, 9.0), unit(0.0, 1.0);
  std::vector<std::pair<double, double>> cases = {{0.0, 1.0}, {1.0, 0.0}, {4e-320, 1.0}, {3.0, 1.0}, {0.1, 0.3}};
  for (int k = 0; k < 200; ++k) cases.push_back({std::pow(10.0, exponent(random)), unit(random) < 0.1 ? 0.0 : unit(random)});
  const double infinity = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [rate, bound] : cases) {
    const double threshold = vs::largestFactorWithin(rate, bound);
    ASSERT_GE(threshold, 0.0) << rate << " " << bound;
    EXPECT_LE(threshold * rate, bound);
    const double next = std::nextafter(threshold, infinity);
    EXPECT_FALSE(next * rate <= bound) << rate << " " << bound;
    std::vector<double> errors = {0.0, -0.0, threshold, -threshold, next, -next, infinity, -infinity, nan,
                                  std::nextafter(threshold, 0.0), std::numeric_limits<double>::max()};
    for (int j = 0; j < 50; ++j) errors.push_back((unit(random) - 0.5) * 4.0 * (threshold > 0.0 ? threshold : 1e-300));
    for (double error : errors)
      EXPECT_EQ(std::fabs(error) * rate <= bound, std::fabs(error) <= threshold) << rate << " " << bound << " " << error;
  }
  EXPECT_LT(vs::largestFactorWithin(infinity, 1.0), 0.0);
  EXPECT_LT(vs::largestFactorWithin(nan, 1.0), 0.0);
}

}  // namespace
