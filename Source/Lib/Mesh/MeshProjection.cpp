#include "Mesh/MeshProjection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Common/Error.h"

namespace vs {

Mat4 Mat4::identity() {
  Mat4 a;
  for (int i = 0; i < 4; ++i) a.m[i][i] = 1.0;
  return a;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 c;
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k)
      c.m[r][k] = a.m[r][0] * b.m[0][k] + a.m[r][1] * b.m[1][k] + a.m[r][2] * b.m[2][k] + a.m[r][3] * b.m[3][k];
  return c;
}

void toGlMatrix(const Mat4& a, float out[16]) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = float(a.m[r][c]);
}

RenderGrid lumaGrid(const Camera& camera, int width, int height) { return RenderGrid{width, height, camera.K}; }

RenderGrid chromaGrid(const Camera& camera, int lumaWidth, int lumaHeight, ChromaFormat format) {
  VS_CHECK(format != ChromaFormat::Yuv400);
  RenderGrid grid{chromaWidth(lumaWidth, format), chromaHeight(lumaHeight, format), camera.K};
  if (format == ChromaFormat::Yuv420) {
    // Luma position x = 2 i + 0.5  <=>  i = x / 2 - 1/4.
    Mat3 scale = Mat3::identity();
    scale[0][0] = scale[1][1] = 0.5;
    scale[0][2] = scale[1][2] = -0.25;
    grid.K = scale * camera.K;
  }
  return grid;
}

Mat4 referenceToVirtualMatrix(const Camera& reference, const Camera& virtualCamera) {
  const RelativePose pose = relativePose(reference, virtualCamera);
  const Mat3 rotation = pose.R * inverse(reference.K);
  Mat4 a;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) a.m[r][k] = rotation[r][k];
    a.m[r][3] = pose.t[r];
  }
  a.m[3][3] = 1.0;
  return a;
}

namespace {

// A reference vertex (u, v, q) lands at virtual pixel h.xy / h.z with h = H (u, v, 1) + q e.
struct VertexToPixel {
  Mat3 H;
  Vec3 e;
};

VertexToPixel vertexToPixel(const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid) {
  const Mat4 toVirtual = referenceToVirtualMatrix(reference, virtualCamera);
  Mat3 rotation;
  Vec3 translation;
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) rotation[r][k] = toVirtual.m[r][k];
    translation[r] = toVirtual.m[r][3];
  }
  return {grid.K * rotation, grid.K * translation};
}

}  // namespace

DisplacementRate pinholeDisplacementRate(const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid) {
  const auto [H, e] = vertexToPixel(reference, virtualCamera, grid);
  return DisplacementRate::pinhole(H, e);
}

ReferenceShift pinholeReferenceShift(const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid) {
  const auto [H, e] = vertexToPixel(reference, virtualCamera, grid);
  return ReferenceShift::pinhole(H, e);
}

Mat4 projectionMatrix(const RenderGrid& grid, const InverseDepthRange& planes) {
  VS_CHECK(grid.width > 0 && grid.height > 0 && planes.hi > planes.lo);
  const Mat3& K = grid.K;
  const double W = grid.width, H = grid.height;
  const double A = (planes.hi + planes.lo) / (planes.hi - planes.lo), B = -2.0 / (planes.hi - planes.lo);
  Mat4 p;
  for (int k = 0; k < 3; ++k) {
    p.m[0][k] = 2.0 / W * K[0][k] + (1.0 / W - 1.0) * K[2][k];
    p.m[1][k] = 2.0 / H * K[1][k] + (1.0 / H - 1.0) * K[2][k];
    p.m[2][k] = A * K[2][k];
    p.m[3][k] = K[2][k];
  }
  p.m[2][3] = B;
  return p;
}

Mat4 meshClipMatrix(const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid,
                    const InverseDepthRange& planes) {
  return projectionMatrix(grid, planes) * referenceToVirtualMatrix(reference, virtualCamera);
}

bool clipToPixel(const Mat4& clip, const RenderGrid& grid, const double vertex[4], double& x, double& y, double& q) {
  double c[4];
  for (int r = 0; r < 4; ++r)
    c[r] = clip.m[r][0] * vertex[0] + clip.m[r][1] * vertex[1] + clip.m[r][2] * vertex[2] + clip.m[r][3] * vertex[3];
  if (!(c[3] > 0.0)) return false;
  // Viewport transform: window = (ndc + 1) size / 2; fragment (i, j) has its centre at (i + 0.5, j + 0.5).
  x = (c[0] / c[3] + 1.0) * 0.5 * grid.width - 0.5;
  y = (c[1] / c[3] + 1.0) * 0.5 * grid.height - 0.5;
  q = vertex[3] / c[3];
  return true;
}

bool sceneInverseDepthRange(const Camera& reference, const DepthRange& range, int depthType, int width, int height,
                            const Camera& virtualCamera, InverseDepthRange& out) {
  const Mat4 toVirtual = referenceToVirtualMatrix(reference, virtualCamera);
  const double levels[2] = {0.0, double(maxDepthLevel(range))};
  const double us[2] = {-0.5, width - 0.5}, vs[2] = {-0.5, height - 0.5};
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double level : levels)
    for (double u : us)
      for (double v : vs) {
        double vertex[4], inverseCameraZ;
        if (!referenceVertex(reference, depthType, u, v, levelToInverseZ(level, range), vertex, inverseCameraZ)) return false;
        const double z = toVirtual.m[2][0] * vertex[0] + toVirtual.m[2][1] * vertex[1] + toVirtual.m[2][2] * vertex[2] +
                         toVirtual.m[2][3] * vertex[3];
        if (!(z > 0.0)) return false;
        const double q = vertex[3] / z;
        lo = std::min(lo, q);
        hi = std::max(hi, q);
      }
  // Between the two levels a DepthType 1 range may pass through 1/Z = 0 (Znear and Zfar of opposite
  // signs): then the points wrap through infinity and no corner bounds them.
  if (depthType == kDepthTypeWorld && (levelToInverseZ(0.0, range) < 0.0) != (levelToInverseZ(levels[1], range) < 0.0))
    return false;
  out = {lo, hi};
  return std::isfinite(lo) && std::isfinite(hi);
}

InverseDepthRange meshInverseDepthRange(const DepthMesh& mesh, const Camera& reference, const Camera& virtualCamera) {
  const Mat4 toVirtual = referenceToVirtualMatrix(reference, virtualCamera);
  const double* zRow = toVirtual.m[2];
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    if (!mesh.valid[i]) continue;
    const float* v = &mesh.vertices[i * 4];
    const double z = zRow[0] * v[0] + zRow[1] * v[1] + zRow[2] * v[2] + zRow[3] * v[3];
    if (!(z > 0.0)) continue;
    const double q = v[3] / z;
    lo = std::min(lo, q);
    hi = std::max(hi, q);
  }
  if (lo > hi) return {0.0, 0.0};
  return {lo, hi};
}

InverseDepthRange clipPlanes(const InverseDepthRange& range) {
  double span = range.hi - range.lo;
  if (!(span > 1e-9 * std::fabs(range.hi))) span = std::max(std::fabs(range.hi), 1e-12);
  return {range.lo - 0.05 * span, range.hi + 0.05 * span};
}

}  // namespace vs
