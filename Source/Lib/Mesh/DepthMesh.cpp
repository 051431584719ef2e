#include "Mesh/DepthMesh.h"

#include <algorithm>
#include <cmath>

#include "Common/Error.h"

namespace vs {

namespace {

// Grid positions along one axis of `size` pixels: -0.5, 0, step, 2 step, ..., size-1, size-0.5.
void gridPositions(int size, int step, std::vector<double>& positions, std::vector<int>& pixels) {
  positions.clear();
  pixels.clear();
  positions.push_back(-0.5);
  for (int p = 0; p < size; p += step) positions.push_back(p);
  if (positions.back() != size - 1) positions.push_back(size - 1);
  positions.push_back(size - 0.5);
  for (double position : positions) pixels.push_back(std::clamp(int(std::lround(position)), 0, size - 1));
}

// The camera depths of two vertices are one surface when 1 - z_min / z_max <= threshold, that is
// q_min >= (1 - threshold) q_max in inverse depth q = 1 / z (q = 0 at infinity).
inline bool sameSurface(double qa, double qb, double threshold) {
  const double lo = std::min(qa, qb), hi = std::max(qa, qb);
  return lo >= (1.0 - threshold) * hi;
}

inline double relativeStep(double qa, double qb) {
  const double hi = std::max(qa, qb);
  return hi > 0.0 ? 1.0 - std::min(qa, qb) / hi : 0.0;
}

}  // namespace

bool referenceVertex(const Camera& reference, int depthType, double u, double v, double inverseZ, double vertex[4],
                     double& inverseCameraZ) {
  if (std::isnan(inverseZ)) return false;
  double a = 1.0, w = inverseZ;
  if (depthType == kDepthTypeWorld) {
    const Vec3 ray = inverse(reference.R) * reference.pixelToCamera(u, v, 1.0);
    if (!(std::fabs(ray.z) > 1e-12 * norm(ray))) return false;  // parallel to the plane z = Z
    a = (1.0 - w * reference.t.z) / ray.z;
  }
  if (w < 0.0) {
    a = -a;
    w = -w;
  }
  if (!(a > 0.0) || !std::isfinite(a) || !std::isfinite(w)) return false;
  vertex[0] = a * u;
  vertex[1] = a * v;
  vertex[2] = a;
  vertex[3] = w;
  inverseCameraZ = w / a;
  return true;
}

DepthMeshBuilder::DepthMeshBuilder(const Camera& reference, const DepthRange& range, int width, int height,
                                   const MeshOptions& options)
    : reference_(reference), options_(options), width_(width), height_(height) {
  VS_CHECK(width > 0 && height > 0 && options.gridStep >= 1);
  VS_CHECK(options.depthType == kDepthTypeCamera || options.depthType == kDepthTypeWorld);
  inverseZ_ = inverseZTable(range);
  if (options.missingDepthLevel >= 0 && size_t(options.missingDepthLevel) < inverseZ_.size())
    inverseZ_[size_t(options.missingDepthLevel)] = std::nan("");
  gridPositions(width, options.gridStep, gridU_, pixelU_);
  gridPositions(height, options.gridStep, gridV_, pixelV_);
  if (options.depthType == kDepthTypeWorld) {
    // As referenceVertex(): a ray (nearly) parallel to the plane z = Z gets D_z = 0, which drops it.
    const Mat3 cameraToWorld = inverse(reference.R);
    worldRayZ_.resize(gridU_.size() * gridV_.size());
    for (size_t r = 0; r < gridV_.size(); ++r)
      for (size_t c = 0; c < gridU_.size(); ++c) {
        const Vec3 ray = cameraToWorld * reference.pixelToCamera(gridU_[c], gridV_[r], 1.0);
        worldRayZ_[r * gridU_.size() + c] = std::fabs(ray.z) > 1e-12 * norm(ray) ? ray.z : 0.0;
      }
  }
}

void DepthMeshBuilder::build(const Plane& depth, DepthMesh& mesh) const {
  VS_CHECK(depth.width == width_ && depth.height == height_);
  const int columns = int(gridU_.size()), rows = int(gridV_.size());
  const size_t count = size_t(columns) * size_t(rows);
  mesh.columns = columns;
  mesh.rows = rows;
  mesh.gridU = gridU_;
  mesh.gridV = gridV_;
  mesh.vertices.assign(count * 4, 0.0f);
  mesh.boundary.assign(count, 0.0f);
  mesh.valid.assign(count, 0);
  mesh.triangles.clear();
  mesh.triangles.reserve(count * 6);
  mesh.points.clear();
  mesh.droppedTriangles = 0;
  std::vector<double> cameraInverseZ(count, 0.0);

  const bool world = options_.depthType == kDepthTypeWorld;
  const double centreZ = reference_.t.z;
  for (int r = 0; r < rows; ++r) {
    const uint16_t* depthRow = depth.row(pixelV_[size_t(r)]);
    for (int c = 0; c < columns; ++c) {
      const size_t i = size_t(r) * columns + c;
      const uint16_t level = depthRow[pixelU_[size_t(c)]];
      double w = level < inverseZ_.size() ? inverseZ_[level] : std::nan("");
      if (std::isnan(w)) continue;
      // referenceVertex() without recomputing the ray per vertex: the same formula, D_z cached.
      double a = 1.0;
      if (world) {
        const double rayZ = worldRayZ_[i];
        if (rayZ == 0.0) continue;
        a = (1.0 - w * centreZ) / rayZ;
      }
      if (w < 0.0) {
        a = -a;
        w = -w;
      }
      if (!(a > 0.0) || !std::isfinite(a)) continue;
      float* vertex = &mesh.vertices[i * 4];
      vertex[0] = float(a * gridU_[size_t(c)]);
      vertex[1] = float(a * gridV_[size_t(r)]);
      vertex[2] = float(a);
      vertex[3] = float(w);
      mesh.valid[i] = 1;
      cameraInverseZ[i] = w / a;
    }
  }

  const double threshold = options_.discontinuityThreshold;
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (sameSurface(cameraInverseZ[a], cameraInverseZ[b], threshold) &&
        sameSurface(cameraInverseZ[b], cameraInverseZ[c], threshold) &&
        sameSurface(cameraInverseZ[a], cameraInverseZ[c], threshold)) {
      mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
      return;
    }
    ++mesh.droppedTriangles;
    mesh.boundary[a] = mesh.boundary[b] = mesh.boundary[c] = 1.0f;
  };
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < columns; ++c) {
      // Corners: 0 (c, r), 1 (c+1, r), 2 (c, r+1), 3 (c+1, r+1).
      const uint32_t q0 = uint32_t(size_t(r) * columns + c), q1 = q0 + 1, q2 = q0 + uint32_t(columns), q3 = q2 + 1;
      const int validCount = mesh.valid[q0] + mesh.valid[q1] + mesh.valid[q2] + mesh.valid[q3];
      if (validCount < 4) {
        // Next to missing data: what is left is a mesh border.
        for (uint32_t q : {q0, q1, q2, q3})
          if (mesh.valid[q]) mesh.boundary[q] = 1.0f;
        if (validCount < 3) {
          mesh.droppedTriangles += 2;
          continue;
        }
        ++mesh.droppedTriangles;
        if (!mesh.valid[q0]) emit(q1, q3, q2);
        else if (!mesh.valid[q1]) emit(q0, q3, q2);
        else if (!mesh.valid[q2]) emit(q0, q1, q3);
        else emit(q0, q1, q2);
        continue;
      }
      // Split along the diagonal whose ends are closer in depth: across a depth step that keeps one
      // triangle whole on each side instead of stretching both.
      if (relativeStep(cameraInverseZ[q0], cameraInverseZ[q3]) <= relativeStep(cameraInverseZ[q1], cameraInverseZ[q2])) {
        emit(q0, q1, q3);
        emit(q0, q3, q2);
      } else {
        emit(q0, q1, q2);
        emit(q1, q3, q2);
      }
    }

  // Border vertices of kept triangles are also drawn as points (see the header).
  std::vector<uint8_t> used(count, 0);
  for (uint32_t index : mesh.triangles) used[index] = 1;
  mesh.points.clear();
  for (size_t i = 0; i < count; ++i)
    if (used[i] && mesh.boundary[i] > 0.0f) mesh.points.push_back(uint32_t(i));
}

}  // namespace vs
