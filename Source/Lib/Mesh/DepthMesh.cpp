#include "Mesh/DepthMesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <utility>

#include "Common/Error.h"
#include "Mesh/MeshErp.h"

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

// Second difference of depth levels along a grid line that still counts as one plane (planar()).
constexpr int kPlanarLevelSlack = 2;

inline double relativeStep(double qa, double qb) {
  const double hi = std::max(qa, qb);
  return hi > 0.0 ? 1.0 - std::min(qa, qb) / hi : 0.0;
}

// A grid cell's triangles, as build() decides them, in one byte: the low 3 bits say how the quad is
// split (kCellTriangles), bits 3 and 4 which of its (at most two) triangles are kept. The adaptive
// merge and the plain grid both write the kept ones from it, so no full-grid index list is stored.
constexpr uint8_t kSplitMain = 0, kSplitAnti = 1;  // four valid corners, split along either diagonal
// 2 + k: only corner k is invalid, one triangle; kNoTriangle: fewer than three valid corners.
constexpr uint8_t kNoTriangle = 6;
constexpr uint8_t kKeptFirst = 8, kKeptSecond = 16;
// The corners (0 (c, r), 1 (c+1, r), 2 (c, r+1), 3 (c+1, r+1)) of each split's triangles, in the order
// they were always emitted in; -1: no second triangle.
constexpr int kCellTriangles[7][2][3] = {{{0, 1, 3}, {0, 3, 2}}, {{0, 1, 2}, {1, 3, 2}}, {{1, 3, 2}, {-1, -1, -1}},
                                         {{0, 3, 2}, {-1, -1, -1}}, {{0, 1, 3}, {-1, -1, -1}}, {{0, 1, 2}, {-1, -1, -1}},
                                         {{-1, -1, -1}, {-1, -1, -1}}};

// Appends the kept triangles of the cell whose corner 0 is vertex q0 (grid `columns` wide).
inline void appendCellTriangles(uint8_t code, uint32_t q0, int columns, std::vector<uint32_t>& triangles) {
  const uint32_t corners[4] = {q0, q0 + 1, q0 + uint32_t(columns), q0 + uint32_t(columns) + 1};
  const int split = code & 7;
  for (int t = 0; t < 2; ++t)
    if (code & (t == 0 ? kKeptFirst : kKeptSecond)) {
      const int* k = kCellTriangles[split][t];
      triangles.insert(triangles.end(), {corners[k[0]], corners[k[1]], corners[k[2]]});
    }
}

// The index of the last of `lines` (-0.5, 0, step, 2 step, ..., size - 1, size - 0.5) at or before
// `position`, clamped to [0, lines.size() - 2]: the cell of the grid along one axis. A binary search
// gives the same; this guesses from the step and corrects the guess against the lines themselves.
inline int cellOf(const std::vector<double>& lines, int step, double position) {
  const int last = int(lines.size()) - 2;
  if (!(position < lines[size_t(last)])) return last;  // also NaN, as the search's end
  if (!(position >= lines[1])) return 0;
  // position / 1 is position: no division for the default step.
  int c = std::min(1 + int(step == 1 ? position : position / double(step)), last);
  while (c > 0 && lines[size_t(c)] > position) --c;
  while (c < last && lines[size_t(c) + 1] <= position) ++c;
  return c;
}

}  // namespace

double largestFactorWithin(double rate, double bound) {
  if (!(rate >= 0.0 && rate < std::numeric_limits<double>::infinity() && bound >= 0.0)) return -1.0;
  auto within = [&](uint64_t bits) {
    double x;
    std::memcpy(&x, &bits, sizeof x);
    return x * rate <= bound;
  };
  // Bisection over the non-negative doubles, whose bit patterns are in the order of their values:
  // within(lo) (0 rate = 0), not within(hi) (infinity rate is infinite, or NaN for rate 0).
  const double infinity = std::numeric_limits<double>::infinity();
  uint64_t lo = 0, hi = 0;
  std::memcpy(&hi, &infinity, sizeof hi);
  while (hi - lo > 1) {
    const uint64_t mid = lo + (hi - lo) / 2;
    (within(mid) ? lo : hi) = mid;
  }
  double x;
  std::memcpy(&x, &lo, sizeof x);
  return x;
}

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
                                   const MeshOptions& options, DisplacementRate rate, ReferenceShift shift)
    : reference_(reference), rate_(std::move(rate)), shift_(std::move(shift)), options_(options), width_(width), height_(height) {
  VS_CHECK(width > 0 && height > 0 && options.gridStep >= 1);
  VS_CHECK(options.depthType == kDepthTypeCamera || options.depthType == kDepthTypeWorld);
  inverseZ_ = inverseZTable(range);
  if (options.missingDepthLevel >= 0 && size_t(options.missingDepthLevel) < inverseZ_.size())
    inverseZ_[size_t(options.missingDepthLevel)] = std::nan("");
  gridPositions(width, options.gridStep, gridU_, pixelU_);
  gridPositions(height, options.gridStep, gridV_, pixelV_);
  if (reference.isEquirectangular()) {  // rays, the wrap column and the poles (MeshErp.h)
    VS_CHECK(options.depthType == kDepthTypeCamera && !rate_);
    erpMeshGrid(reference, gridU_, pixelU_, gridV_, erpRays_, erpPoleRows_);
  }
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

void DepthMeshBuilder::build(const Plane& depth, DepthMesh& mesh, const Plane* luma) const {
  VS_CHECK(depth.width == width_ && depth.height == height_);
  const int columns = int(gridU_.size()), rows = int(gridV_.size());
  const size_t count = size_t(columns) * size_t(rows);
  mesh.columns = columns;
  mesh.rows = rows;
  mesh.gridStep = options_.gridStep;
  mesh.gridU = gridU_;
  mesh.gridV = gridV_;
  mesh.vertices.assign(count * 4, 0.0f);
  mesh.boundary.assign(count, 0);
  mesh.valid.assign(count, 0);
  mesh.triangles.clear();
  mesh.points.clear();
  mesh.farthestOrphans.clear();
  mesh.droppedTriangles = 0;
  mesh.gridTriangles = 0;
  std::vector<double> cameraInverseZ(count, 0.0);

  const bool world = options_.depthType == kDepthTypeWorld;
  // Levels are affine in the image on a plane only for camera depth (DepthType 0).
  const bool planarEdges = options_.depthType == kDepthTypeCamera;  // ERP: its own form (MeshErp.h)
  const double centreZ = reference_.t.z;
  for (int r = 0; r < rows; ++r) {
    const uint16_t* depthRow = depth.row(pixelV_[size_t(r)]);
    for (int c = 0; c < columns; ++c) {
      const size_t i = size_t(r) * columns + c;
      const uint16_t sampleLevel = depthRow[pixelU_[size_t(c)]];
      double w = sampleLevel < inverseZ_.size() ? inverseZ_[sampleLevel] : std::nan("");
      if (std::isnan(w)) continue;
      if (!erpRays_.empty()) {  // ERP: (ray, 1 / distance) (MeshErp.h)
        if (!(w >= 0.0) || !std::isfinite(w)) continue;
        const Vec3& ray = erpRays_[i];
        float* vertex = &mesh.vertices[i * 4];
        vertex[0] = float(ray.x);
        vertex[1] = float(ray.y);
        vertex[2] = float(ray.z);
        vertex[3] = float(w);
        mesh.valid[i] = 1;
        cameraInverseZ[i] = w;
        continue;
      }
      // referenceVertex() without recomputing the ray per vertex: the same formula, D_z cached.
      if (!world) {  // a = 1 (a negative w would make it -1: not in front): a u, a v, w / a are u, v, w
        if (w < 0.0) continue;
        float* vertex = &mesh.vertices[i * 4];
        vertex[0] = float(gridU_[size_t(c)]);
        vertex[1] = float(gridV_[size_t(r)]);
        vertex[2] = 1.0f;
        vertex[3] = float(w);
        mesh.valid[i] = 1;
        cameraInverseZ[i] = w;
        continue;
      }
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

  if (!erpPoleRows_.empty()) joinErpPoleRows(erpPoleRows_, mesh, cameraInverseZ);

  const double threshold = options_.discontinuityThreshold;
  // A grid edge from vertex a to vertex b lies on a plane when it belongs to four valid vertices in a
  // row on its line (a and b, and two more before, after, or one on each side) whose depth levels
  // step evenly: a plane's levels are affine in the image (DepthType 0), so there the steps differ
  // by at most kPlanarLevelSlack (rounding of the levels). A surface seen at a grazing angle steps by
  // a large relative depth from sample to sample, yet is one surface; a step between two surfaces is
  // not even with the steps beside it.
  auto planar = [&](uint32_t a, uint32_t b) {
    const int ra = int(a / uint32_t(columns)), ca = int(a % uint32_t(columns));
    const int dr = int(b / uint32_t(columns)) - ra, dc = int(b % uint32_t(columns)) - ca;
    int line[6];  // levels at a + k d, k = -2 .. 3; INT_MIN where not a valid vertex
    for (int k = -2; k <= 3; ++k) {
      const int r = ra + k * dr, c = ca + k * dc;
      const bool inside = r >= 0 && c >= 0 && r < rows && c < columns;
      const size_t i = inside ? size_t(r) * columns + c : 0;
      // A valid vertex's level is the depth sample it read.
      line[k + 2] = inside && mesh.valid[i] ? int(depth.row(pixelV_[size_t(r)])[pixelU_[size_t(c)]])
                                            : std::numeric_limits<int>::min();
    }
    if (!erpRays_.empty()) return erpEdgeOnPlane(reference_, gridU_, gridV_, erpPoleRows_, ra, ca, dr, dc, line);
    const int step = line[3] - line[2];
    for (int first = 0; first <= 2; ++first) {  // windows line[first .. first + 3], all hold a and b
      bool even = true;
      for (int k = first; k < first + 3 && even; ++k)
        even = line[k] != std::numeric_limits<int>::min() && line[k + 1] != std::numeric_limits<int>::min() &&
               std::abs((line[k + 1] - line[k]) - step) <= kPlanarLevelSlack;
      if (even) return true;
    }
    return false;
  };
  // 0: two surfaces; 1: within the threshold; 2: on a plane (planar()). `same`: sameSurface(a, b).
  auto connection = [&](uint32_t a, uint32_t b, bool same) {
    if (same) return 1;
    return planarEdges && planar(a, b) ? 2 : 0;
  };
  // sameSurface() of the grid edges of the cell row being triangulated, each computed once in a pass over
  // the row (an edge belongs to up to four triangles): from (r, c) to (r, c + 1) (top), from (r + 1, c) to
  // (r + 1, c + 1) (bottom, the next row's top) and from (r, c) to (r + 1, c) (down).
  std::vector<uint8_t> sameTop(size_t(columns), 0), sameBottom(size_t(columns), 0), sameDown(size_t(columns), 0);
  std::vector<uint8_t> cellSplitRow(size_t(columns), 0);  // each cell of the row: bit 0 split, bit 1 its diagonal's sameSurface()
  auto sameRow = [&](int r, std::vector<uint8_t>& same) {
    const double* z = &cameraInverseZ[size_t(r) * size_t(columns)];
    for (int c = 0; c + 1 < columns; ++c) same[size_t(c)] = sameSurface(z[c], z[c + 1], threshold);
  };
  // A triangle of the cell whose corners (0 (c, r), 1 (c+1, r), 2 (c, r+1), 3 (c+1, r+1)) are vertices
  // q[0 .. 3], given by its corners k[0 .. 2], is kept when its three edges are connected. Its diagonal
  // edge also counts as connected when the other two are and one of them lies on a plane: the diagonal's
  // own line may leave the grid (near the picture's border) before it holds four vertices.
  auto kept = [&](const uint32_t q[4], const int k[3], int c) {
    int link[3];
    bool diagonal[3];
    for (int e = 0; e < 3; ++e) {
      const int from = k[e], to = k[(e + 1) % 3];
      const int pair = (1 << from) | (1 << to);
      diagonal[e] = pair == 9 || pair == 6;  // corners 0 and 3, or 1 and 2
      const bool same = pair == 3    ? sameTop[size_t(c)] != 0
                        : pair == 12 ? sameBottom[size_t(c)] != 0
                        : pair == 5  ? sameDown[size_t(c)] != 0
                        : pair == 10 ? sameDown[size_t(c) + 1] != 0
                                     : sameSurface(cameraInverseZ[q[from]], cameraInverseZ[q[to]], threshold);
      link[e] = connection(q[from], q[to], same);
    }
    for (int e = 0; e < 3; ++e) {
      if (link[e] || !diagonal[e]) continue;
      const int other1 = link[(e + 1) % 3], other2 = link[(e + 2) % 3];
      if (other1 && other2 && (other1 == 2 || other2 == 2)) link[e] = 2;
    }
    return link[0] && link[1] && link[2];
  };
  // Each cell's split and kept triangles (kCellTriangles); the vertices of kept triangles are `used`.
  const int cellsX = columns - 1;
  // Kept in the mesh (cellSplit): edgeAt reads the split from it.
  std::vector<uint8_t>& cellCode = mesh.cellSplit;
  cellCode.assign(size_t(cellsX) * size_t(rows - 1), kNoTriangle);
  std::vector<uint8_t> used(count, 0);
  auto emit = [&](const uint32_t q[4], const int k[3], int column) {
    const uint32_t a = q[k[0]], b = q[k[1]], c = q[k[2]];
    if (kept(q, k, column)) {
      used[a] = used[b] = used[c] = 1;
      ++mesh.gridTriangles;
      return true;
    }
    ++mesh.droppedTriangles;
    mesh.boundary[a] = mesh.boundary[b] = mesh.boundary[c] = 1;
    return false;
  };
  if (rows > 1) sameRow(0, sameBottom);
  for (int r = 0; r + 1 < rows; ++r) {
    std::swap(sameTop, sameBottom);
    sameRow(r + 1, sameBottom);
    {
      const double* z0 = &cameraInverseZ[size_t(r) * size_t(columns)];
      const double* z1 = z0 + columns;
      for (int c = 0; c < columns; ++c) sameDown[size_t(c)] = sameSurface(z0[c], z1[c], threshold);
      // A cell of four valid corners is split along the diagonal whose ends are closer in depth: across
      // a depth step that keeps one triangle whole on each side instead of stretching both. Its
      // diagonal's sameSurface() beside it (bit 1).
      constexpr double kInfinity = std::numeric_limits<double>::infinity();
      for (int c = 0; c + 1 < columns; ++c) {
        // Equal finite ends (flat depth) have relative step 0, which is at most the other diagonal's
        // unless that is NaN (both its ends infinite): the same decision without the two divisions.
        const bool flat = z0[c] == z1[c + 1] && z0[c] < kInfinity && std::min(z0[c + 1], z1[c]) < kInfinity;
        const bool anti = !flat && !(relativeStep(z0[c], z1[c + 1]) <= relativeStep(z0[c + 1], z1[c]));
        const bool same = anti ? sameSurface(z0[c + 1], z1[c], threshold) : sameSurface(z0[c], z1[c + 1], threshold);
        cellSplitRow[size_t(c)] = uint8_t((anti ? 1 : 0) | (same ? 2 : 0));
      }
    }
    for (int c = 0; c + 1 < columns; ++c) {
      uint8_t& code = cellCode[size_t(r) * size_t(cellsX) + size_t(c)];
      const uint32_t q[4] = {uint32_t(size_t(r) * columns + c), uint32_t(size_t(r) * columns + c) + 1,
                             uint32_t(size_t(r + 1) * columns + c), uint32_t(size_t(r + 1) * columns + c) + 1};
      const int validCount = mesh.valid[q[0]] + mesh.valid[q[1]] + mesh.valid[q[2]] + mesh.valid[q[3]];
      if (validCount < 4) {
        // Next to missing data: what is left is a mesh border.
        for (uint32_t corner : q)
          if (mesh.valid[corner]) mesh.boundary[corner] = 1;
        if (validCount < 3) {
          mesh.droppedTriangles += 2;
          continue;
        }
        ++mesh.droppedTriangles;
        int missing = 0;
        while (mesh.valid[q[missing]]) ++missing;
        code = uint8_t(2 + missing);
      } else {
        const bool anti = (cellSplitRow[size_t(c)] & 1) != 0;
        code = anti ? kSplitAnti : kSplitMain;
        // Every edge within the threshold (the common case): both triangles kept, as kept() finds.
        if ((cellSplitRow[size_t(c)] & 2) && sameTop[size_t(c)] && sameBottom[size_t(c)] && sameDown[size_t(c)] &&
            sameDown[size_t(c) + 1]) {
          used[q[0]] = used[q[1]] = used[q[2]] = used[q[3]] = 1;
          mesh.gridTriangles += 2;
          code = uint8_t(code | kKeptFirst | kKeptSecond);
          continue;
        }
      }
      const int split = code;
      for (int t = 0; t < 2; ++t) {
        const int* k = kCellTriangles[split][t];
        if (k[0] >= 0 && emit(q, k, c)) code = uint8_t(code | (t == 0 ? kKeptFirst : kKeptSecond));
      }
    }
  }

  // Border vertices of kept triangles, and valid vertices without a kept triangle unless nothing
  // around them is farther, are also drawn as points (see the header).
  // True when no valid vertex among the 8 around vertex i is farther.
  auto farthestAround = [&](size_t i) {
    const int r = int(i / size_t(columns)), c = int(i % size_t(columns));
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int nr = r + dr, nc = c + dc;
        if ((dr || dc) && nr >= 0 && nc >= 0 && nr < rows && nc < columns) {
          const size_t k = size_t(nr) * columns + nc;
          if (mesh.valid[k] && cameraInverseZ[k] < cameraInverseZ[i]) return false;
        }
      }
    return true;
  };
  for (size_t i = 0; i < count; ++i) {
    if (used[i] ? mesh.boundary[i] != 0 : mesh.valid[i] && !farthestAround(i)) mesh.points.push_back(uint32_t(i));
    else if (!used[i] && mesh.valid[i]) mesh.farthestOrphans.push_back(uint32_t(i));
  }
  // The adaptive mesh has at most the grid's triangles (a merged block of s x s cells, s >= 2, is at
  // most 4 s triangles against the grid's 2 s^2): one allocation, of which only the used part is touched.
  mesh.triangles.reserve(mesh.gridTriangles * 3);
  if (rate_ && merge(mesh, cameraInverseZ, cellCode, luma && luma->width == width_ && luma->height == height_ ? luma : nullptr))
    return;
  // The grid's triangles as they are, cell by cell.
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < columns; ++c)
      appendCellTriangles(cellCode[size_t(r) * size_t(cellsX) + size_t(c)], uint32_t(size_t(r) * columns + c), columns,
                          mesh.triangles);
}

bool DepthMesh::edgeAt(double u, double v) const {
  if (columns < 2 || rows < 2) return false;
  // The cell: the last grid line at or before the position, clamped to the grid.
  const int c = cellOf(gridU, gridStep, u), r = cellOf(gridV, gridStep, v);
  const size_t q0 = size_t(r) * size_t(columns) + size_t(c), q1 = q0 + 1, q2 = q0 + size_t(columns), q3 = q2 + 1;
  // Most cells have no corner on a dropped triangle: no weight can make them an edge.
  if (!(boundary[q0] | boundary[q1] | boundary[q2] | boundary[q3])) return false;
  const double fu = (u - gridU[size_t(c)]) / (gridU[size_t(c) + 1] - gridU[size_t(c)]);
  const double fv = (v - gridV[size_t(r)]) / (gridV[size_t(r) + 1] - gridV[size_t(r)]);
  // Barycentric weights of the triangle's corners; a corner counts when its weight is above the
  // position's float rounding (as the interpolated flag of a rasterised triangle is above 0 there).
  constexpr double kWeight = 1e-3;
  auto on = [&](size_t corner, double weight) { return weight > kWeight && boundary[corner] != 0; };
  if ((cellSplit[size_t(r) * size_t(columns - 1) + size_t(c)] & 7) != kSplitAnti)
    return fu >= fv ? on(q0, 1.0 - fu) || on(q1, fu - fv) || on(q3, fv) : on(q0, 1.0 - fv) || on(q3, fu) || on(q2, fv - fu);
  return fu + fv <= 1.0 ? on(q0, 1.0 - fu - fv) || on(q1, fu) || on(q2, fv)
                        : on(q1, 1.0 - fv) || on(q2, 1.0 - fu) || on(q3, fu + fv - 1.0);
}

bool DepthMeshBuilder::merge(DepthMesh& mesh, const std::vector<double>& inverseCameraZ,
                             const std::vector<uint8_t>& cellCode, const Plane* luma) const {
  const int columns = mesh.columns, rows = mesh.rows;
  const int cellsX = columns - 1, cellsY = rows - 1;
  constexpr int kMaxLevel = 7;  // blocks of at most 128 x 128 cells
  // ok[k][block]: block (bx, by) of 2^k x 2^k cells is merged as a whole. Level 0: a cell both of
  // whose triangles are kept.
  std::vector<std::vector<uint8_t>> ok(1);
  std::vector<int> blocksX(1, cellsX), blocksY(1, cellsY);
  ok[0].assign(size_t(cellsX) * size_t(cellsY), 0);
  auto vertexIndex = [&](int x, int y) { return size_t(y) * size_t(columns) + size_t(x); };
  for (size_t cell = 0; cell < ok[0].size(); ++cell) ok[0][cell] = (cellCode[cell] & (kKeptFirst | kKeptSecond)) == (kKeptFirst | kKeptSecond);
  const double halfBound = 0.5 * std::max(options_.maxError, 0.0);
  // MeshMaxColourError: each vertex's tolerance in q for a block plane above its sample (colourAbove:
  // plane - q > 0) and below it. Where a block is off by dq at a sample, the virtual pixel that truly
  // shows the sample shows the reference position dq (du, dv) before it instead (ReferenceShift: the
  // texture moves by dq (du, dv) there), a colour change of about |dq| |(du, dv)| times the luma step
  // from the sample to its neighbour one pixel back along dq (du, dv) (interpolated between samples where
  // the shift is not along a row or column) while that is at most a pixel. Half the bound, as for
  // MeshMaxError. Only the step on the side the shift goes counts: a sample next to a texture edge may
  // move away from it by a whole MeshMaxError, not towards it.
  // colourBound: (above, below) of each vertex, side by side.
  std::vector<float> colourBound;
  if (luma && shift_ && options_.maxColourError > 0.0) {
    colourBound.resize(2 * mesh.vertexCount());
    float* colourAbove = colourBound.data();
    float* colourBelow = colourBound.data() + 1;
    const double halfColour = 0.5 * options_.maxColourError;
    constexpr float kNoBound = std::numeric_limits<float>::infinity();
    auto sample = [&](double x, double y) {  // bilinear, clamped to the picture
      x = std::clamp(x, 0.0, double(width_ - 1));
      y = std::clamp(y, 0.0, double(height_ - 1));
      const int x0 = std::min(int(x), width_ - 1), y0 = std::min(int(y), height_ - 1);
      const int x1 = std::min(x0 + 1, width_ - 1), y1 = std::min(y0 + 1, height_ - 1);
      const double fx = x - x0, fy = y - y0;
      const double top = (1.0 - fx) * luma->at(x0, y0) + fx * luma->at(x1, y0);
      const double bottom = (1.0 - fx) * luma->at(x0, y1) + fx * luma->at(x1, y1);
      return (1.0 - fy) * top + fy * bottom;
    };
    // Rectified or parallel cameras: the shift is the same at every vertex (ReferenceShift::uniform), so
    // it and its length are computed once, and the bound of each whole luma step once (a table): the
    // same expressions on the same values, without a shift, a square root and two divisions per vertex.
    double uniformLimit = 0.0, uniformDu = 0.0, uniformDv = 0.0, uniformLength = 0.0;
    const bool uniform = shift_.uniform(uniformLimit);
    const bool uniformShifts = uniform && shift_(0.0, 0.0, 0.0, uniformDu, uniformDv);
    if (uniformShifts) uniformLength = std::sqrt(uniformDu * uniformDu + uniformDv * uniformDv);
    constexpr int kStepTable = 1024;  // whole luma steps 0 .. 1023 (10-bit samples)
    float stepBound[kStepTable];
    if (uniformShifts && uniformLength > 0.0 && std::isfinite(uniformLength)) {
      stepBound[0] = kNoBound;
      for (int step = 1; step < kStepTable; ++step) stepBound[step] = float(halfColour / (double(step) * uniformLength));
    }
    for (int r = 0; r < rows; ++r) {
      const int py = pixelV_[size_t(r)];
      const uint16_t* row = luma->row(py);
      for (int c = 0; c < columns; ++c) {
        const size_t i = vertexIndex(c, r);
        colourAbove[2 * i] = colourBelow[2 * i] = kNoBound;
        // Only the corners of mergeable cells are ever tested.
        const bool tested = (r > 0 && c > 0 && ok[0][size_t(r - 1) * size_t(cellsX) + size_t(c - 1)]) ||
                            (r > 0 && c < cellsX && ok[0][size_t(r - 1) * size_t(cellsX) + size_t(c)]) ||
                            (r < cellsY && c > 0 && ok[0][size_t(r) * size_t(cellsX) + size_t(c - 1)]) ||
                            (r < cellsY && c < cellsX && ok[0][size_t(r) * size_t(cellsX) + size_t(c)]);
        if (!tested) continue;
        double du = 0.0, dv = 0.0, length;
        const bool same = uniform && std::fabs(inverseCameraZ[i]) <= uniformLimit;
        if (same) {
          if (!uniformShifts) continue;
          du = uniformDu;
          dv = uniformDv;
          length = uniformLength;
        } else {
          if (!shift_(mesh.gridU[size_t(c)], mesh.gridV[size_t(r)], inverseCameraZ[i], du, dv)) continue;
          length = std::sqrt(du * du + dv * dv);
        }
        if (!(length > 0.0) || !std::isfinite(length)) continue;
        const int px = pixelU_[size_t(c)];
        const double centre = row[px];
        double forward, backward;
        if (dv == 0.0) {  // along the row (rectified cameras): the neighbours themselves
          const int ahead = du > 0.0 ? std::min(px + 1, width_ - 1) : std::max(px - 1, 0);
          const int behind = du > 0.0 ? std::max(px - 1, 0) : std::min(px + 1, width_ - 1);
          if (same) {  // whole steps: the table
            const int forwardStep = std::abs(int(row[ahead]) - int(row[px]));
            const int backwardStep = std::abs(int(row[behind]) - int(row[px]));
            if (forwardStep < kStepTable && backwardStep < kStepTable) {
              colourAbove[2 * i] = stepBound[backwardStep];
              colourBelow[2 * i] = stepBound[forwardStep];
              continue;
            }
          }
          forward = std::fabs(row[ahead] - centre);
          backward = std::fabs(row[behind] - centre);
        } else {
          const double ex = du / length, ey = dv / length;
          forward = std::fabs(sample(px + ex, py + ey) - centre);
          backward = std::fabs(sample(px - ex, py - ey) - centre);
        }
        if (backward > 0.0) colourAbove[2 * i] = float(halfColour / (backward * length));
        if (forward > 0.0) colourBelow[2 * i] = float(halfColour / (forward * length));
      }
    }
  }
  // Whether every vertex of the block lies within the tolerance of the two triangles through its corners
  // (split along the diagonal from (x0, y0) to (x1, y1)). The tolerance in q is the bound over the
  // largest displacement rate at the corners; half the bound, since the drawn triangles interpolate
  // vertices that are themselves up to the tolerance off.
  std::vector<double> blockDu;  // planarBlock's scratch: each column's du in the block
  // Rectified or parallel cameras: one rate for every vertex (DisplacementRate::uniform). Otherwise each
  // vertex's displacement rate, computed when a block first has it as a corner (NaN before).
  double uniformRateLimit = 0.0;
  const bool uniformRate = rate_.uniform(uniformRateLimit);
  const double rateEverywhere = uniformRate ? rate_(0.0, 0.0, 0.0) : 0.0;
  std::vector<double> cornerRate(uniformRate ? 0 : mesh.vertexCount(), std::numeric_limits<double>::quiet_NaN());
  // |error| rateEverywhere <= halfBound iff |error| <= rateThreshold (largestFactorWithin).
  const double rateThreshold = uniformRate ? largestFactorWithin(rateEverywhere, halfBound) : 0.0;
  // The rows of planarBlock's block; withinRate(error): the displacement test.
  auto rowsWithin = [&](int x0, int y0, int y1, int n, double q00, double upperU, double upperV, double lowerU,
                        double lowerV, double sv, auto withinRate) {
    const double v0 = mesh.gridV[size_t(y0)];
    for (int y = y0; y <= y1; ++y) {
      const double dv = (mesh.gridV[size_t(y)] - v0) * sv;
      const double upperRow = dv * upperV, lowerRow = q00 + dv * lowerV;
      const double* q = &inverseCameraZ[vertexIndex(x0, y)];
      const bool above = !colourBound.empty();
      // Within the tolerance: the displacement (q's error times the rate) within half MeshMaxError, and
      // q's error within the colour tolerance on its side. A whole row is tested without a branch per
      // vertex (the same arithmetic; a NaN error fails), and the block fails after the first row that does.
      // Neither colour bound is negative, so the one on the other side than the error always holds: testing
      // both is testing the one on its side, without a branch on the error's sign (which is unpredictable).
      const double* du = blockDu.data();
      int split = 0;  // the lower triangle's part of the row: du < dv
      while (split < n && !(du[split] >= dv)) ++split;
      bool rowWithin = true;
      if (above) {
        const float* bound = colourBound.data() + 2 * vertexIndex(x0, y);  // (above, below) per vertex
        for (int i = 0; i < split; ++i) {
          const double error = (lowerRow + du[i] * lowerU) - q[i];
          rowWithin &= withinRate(error) & (error <= double(bound[2 * i])) & (-error <= double(bound[2 * i + 1]));
        }
        for (int i = split; i < n; ++i) {
          const double error = (q00 + du[i] * upperU + upperRow) - q[i];
          rowWithin &= withinRate(error) & (error <= double(bound[2 * i])) & (-error <= double(bound[2 * i + 1]));
        }
      } else {
        for (int i = 0; i < split; ++i) rowWithin &= withinRate((lowerRow + du[i] * lowerU) - q[i]);
        for (int i = split; i < n; ++i) rowWithin &= withinRate((q00 + du[i] * upperU + upperRow) - q[i]);
      }
      if (!rowWithin) return false;
    }
    return true;
  };
  auto planarBlock = [&](int x0, int y0, int width, int height) {
    const int x1 = x0 + width, y1 = y0 + height;
    const double u0 = mesh.gridU[size_t(x0)], u1 = mesh.gridU[size_t(x1)];
    const double v0 = mesh.gridV[size_t(y0)], v1 = mesh.gridV[size_t(y1)];
    const double q00 = inverseCameraZ[vertexIndex(x0, y0)], q10 = inverseCameraZ[vertexIndex(x1, y0)];
    const double q01 = inverseCameraZ[vertexIndex(x0, y1)], q11 = inverseCameraZ[vertexIndex(x1, y1)];
    double rate = 0.0;
    const int cornerX[4] = {x0, x1, x0, x1}, cornerY[4] = {y0, y0, y1, y1};
    for (int k = 0; k < 4; ++k) {
      const size_t i = vertexIndex(cornerX[k], cornerY[k]);
      double r;
      if (uniformRate) {
        r = std::fabs(inverseCameraZ[i]) <= uniformRateLimit
                ? rateEverywhere
                : rate_(mesh.gridU[size_t(cornerX[k])], mesh.gridV[size_t(cornerY[k])], inverseCameraZ[i]);
      } else {
        if (std::isnan(cornerRate[i]))
          cornerRate[i] = rate_(mesh.gridU[size_t(cornerX[k])], mesh.gridV[size_t(cornerY[k])], inverseCameraZ[i]);
        r = cornerRate[i];
      }
      if (!(r < std::numeric_limits<double>::infinity())) return false;  // not in front of the virtual camera
      rate = std::max(rate, r);
    }
    const double su = 1.0 / (u1 - u0), sv = 1.0 / (v1 - v0);
    const int n = width + 1;
    blockDu.resize(size_t(n));
    for (int i = 0; i < n; ++i) blockDu[size_t(i)] = (mesh.gridU[size_t(x0 + i)] - u0) * su;  // increasing
    // The plane at (du, dv): q00 + du (q10 - q00) + dv (q11 - q10) where du >= dv, else
    // q00 + dv (q01 - q00) + du (q11 - q01); each row's dv terms are computed once.
    const double upperU = q10 - q00, upperV = q11 - q10, lowerU = q11 - q01, lowerV = q01 - q00;
    // |error| rate <= halfBound, or, at the rate every vertex has (rectified cameras), the same as
    // |error| <= rateThreshold (product below): one multiplication less per vertex.
    if (uniformRate && rate == rateEverywhere && rateEverywhere < std::numeric_limits<double>::infinity())
      return rowsWithin(x0, y0, y1, n, q00, upperU, upperV, lowerU, lowerV, sv,
                        [threshold = rateThreshold](double error) { return std::fabs(error) <= threshold; });
    return rowsWithin(x0, y0, y1, n, q00, upperU, upperV, lowerU, lowerV, sv,
                      [rate, halfBound](double error) { return std::fabs(error) * rate <= halfBound; });
  };
  for (int k = 1; k <= kMaxLevel; ++k) {
    const int bx = cellsX >> k, by = cellsY >> k;
    if (bx == 0 || by == 0) break;
    const std::vector<uint8_t>& child = ok.back();
    const int childX = blocksX.back();
    std::vector<uint8_t> level(size_t(bx) * size_t(by), 0);
    bool any = false;
    for (int y = 0; y < by; ++y)
      for (int x = 0; x < bx; ++x) {
        const size_t c = size_t(2 * y) * size_t(childX) + size_t(2 * x);
        if (!(child[c] && child[c + 1] && child[c + size_t(childX)] && child[c + size_t(childX) + 1])) continue;
        const bool merged = planarBlock(x << k, y << k, 1 << k, 1 << k);
        level[size_t(y) * size_t(bx) + size_t(x)] = merged;
        any = any || merged;
      }
    if (!any) break;
    ok.push_back(std::move(level));
    blocksX.push_back(bx);
    blocksY.push_back(by);
  }
  // From blocks of 2 x 2 cells up, even where none merged: rectangles of two cells still may.
  const int top = std::max(int(ok.size()) - 1, 1);

  // The leaves, top-down: a merged block not inside a larger merged one, a 2:1 rectangle of two merged
  // blocks whose parent did not merge, cells elsewhere. Every leaf's corners are marked: a merged
  // block's or rectangle's sides pass through the marked vertices of its neighbours.
  struct Leaf {
    int x, y, width, height;  // x, y: first cell; a single cell (width 0) keeps its grid triangles
  };
  std::vector<Leaf> leaves;
  std::vector<uint8_t> corner(mesh.vertexCount(), 0);
  auto addLeaf = [&](int x, int y, int width, int height) {
    const int w = std::max(width, 1), h = std::max(height, 1);
    leaves.push_back({x, y, width, height});
    corner[vertexIndex(x, y)] = corner[vertexIndex(x + w, y)] = 1;
    corner[vertexIndex(x, y + h)] = corner[vertexIndex(x + w, y + h)] = 1;
  };
  auto merged = [&](int level, int bx, int by) {
    return level < int(ok.size()) && bx < blocksX[size_t(level)] && by < blocksY[size_t(level)] &&
           ok[size_t(level)][size_t(by) * size_t(blocksX[size_t(level)]) + size_t(bx)];
  };
  // Recursive through its first argument (itself), without a std::function call per block.
  auto collect = [&](auto& self, int level, int bx, int by) -> void {
    const int x = bx << level, y = by << level;
    if (x >= cellsX || y >= cellsY) return;
    if (level == 0) return addLeaf(x, y, 0, 0);
    if (merged(level, bx, by)) return addLeaf(x, y, 1 << level, 1 << level);
    // The block did not merge: a pair of its merged halves (two children side by side, or one above the
    // other) still may, as a 2:1 rectangle tested like a block.
    bool done[2][2] = {{false, false}, {false, false}};  // [j][i]
    {
      const int half = 1 << (level - 1);
      auto child = [&](int i, int j) { return merged(level - 1, 2 * bx + i, 2 * by + j); };
      for (int j = 0; j < 2; ++j)
        if (child(0, j) && child(1, j) && planarBlock(x, y + j * half, 2 * half, half)) {
          addLeaf(x, y + j * half, 2 * half, half);
          done[j][0] = done[j][1] = true;
        }
      if (!done[0][0] && !done[1][0])
        for (int i = 0; i < 2; ++i)
          if (child(i, 0) && child(i, 1) && planarBlock(x + i * half, y, half, 2 * half)) {
            addLeaf(x + i * half, y, half, 2 * half);
            done[0][i] = done[1][i] = true;
          }
    }
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        if (!done[j][i]) self(self, level - 1, 2 * bx + i, 2 * by + j);
  };
  for (int by = 0; by << top < cellsY; ++by)
    for (int bx = 0; bx << top < cellsX; ++bx) collect(collect, top, bx, by);
  if (std::all_of(leaves.begin(), leaves.end(), [](const Leaf& leaf) { return leaf.width == 0; })) return false;  // nothing merged

  std::vector<uint32_t>& triangles = mesh.triangles;
  std::vector<uint32_t> ring;
  for (const Leaf& leaf : leaves) {
    if (leaf.width == 0) {
      appendCellTriangles(cellCode[size_t(leaf.y) * size_t(cellsX) + size_t(leaf.x)], uint32_t(vertexIndex(leaf.x, leaf.y)),
                          columns, triangles);
      continue;
    }
    const int x0 = leaf.x, y0 = leaf.y, x1 = x0 + leaf.width, y1 = y0 + leaf.height;
    // The block's outline, clockwise from (x0, y0), through every marked vertex.
    ring.clear();
    for (int x = x0; x < x1; ++x)
      if (corner[vertexIndex(x, y0)]) ring.push_back(uint32_t(vertexIndex(x, y0)));
    for (int y = y0; y < y1; ++y)
      if (corner[vertexIndex(x1, y)]) ring.push_back(uint32_t(vertexIndex(x1, y)));
    const size_t last = ring.size();  // where (x1, y1) is
    for (int x = x1; x > x0; --x)
      if (corner[vertexIndex(x, y1)]) ring.push_back(uint32_t(vertexIndex(x, y1)));
    for (int y = y1; y > y0; --y)
      if (corner[vertexIndex(x0, y)]) ring.push_back(uint32_t(vertexIndex(x0, y)));
    if (ring.size() == 4) {  // the two triangles the block was tested against
      triangles.insert(triangles.end(), {ring[0], ring[1], ring[2], ring[0], ring[2], ring[3]});
      continue;
    }
    ring.push_back(ring[0]);
    // Each of the two tested triangles, (x0, y0) (x1, y0) (x1, y1) and (x1, y1) (x0, y1) (x0, y0), with the
    // marked vertices on its two outer sides: polygon p[0 .. m] whose corners are p[0], p[j] and p[m]
    // (p[m] to p[0] is the diagonal). Triangulated without a vertex of its own: a fan from p[m] over the
    // first side but its last piece, then a fan from the vertex before p[j] over the second side; m - 1
    // triangles, each inside the tested triangle, so no sample is farther from them than from it plus
    // the vertices' own tolerance. The block takes n - 2 triangles for n marked vertices.
    auto half = [&](size_t first, size_t corner2, size_t end) {  // ring indices of p[0], p[j], p[m]
      for (size_t k = first; k + 2 <= corner2; ++k) triangles.insert(triangles.end(), {ring[end], ring[k], ring[k + 1]});
      const uint32_t pivot = ring[corner2 - 1];
      for (size_t k = corner2; k < end; ++k) triangles.insert(triangles.end(), {pivot, ring[k], ring[k + 1]});
    };
    size_t topRight = 0, bottomLeft = last;  // ring indices of (x1, y0) and (x0, y1)
    while (ring[topRight] != uint32_t(vertexIndex(x1, y0))) ++topRight;
    while (ring[bottomLeft] != uint32_t(vertexIndex(x0, y1))) ++bottomLeft;
    half(0, topRight, last);
    half(last, bottomLeft, ring.size() - 1);
  }
  return true;
}

}  // namespace vs
