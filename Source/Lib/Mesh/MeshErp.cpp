#include "Mesh/MeshErp.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "Common/Error.h"

namespace vs {

void erpMeshGrid(const Camera& reference, std::vector<double>& gridU, std::vector<int>& pixelU,
                 const std::vector<double>& gridV, std::vector<Vec3>& rays, std::vector<int>& poleRows) {
  VS_CHECK(reference.isEquirectangular() && gridU.size() >= 3 && gridU.size() == pixelU.size());
  const EquirectangularRange& erp = reference.erp;
  if (erp.wraps()) {
    // -0.5, 0, ..., W-1, W-0.5  ->  0, ..., W-1, W (pixel 0 again, a whole turn on).
    gridU.erase(gridU.begin());
    pixelU.erase(pixelU.begin());
    gridU.back() = erp.width;
    pixelU.back() = 0;
  }
  poleRows.clear();
  for (size_t r = 0; r < gridV.size(); ++r) {
    const double latitude = erp.latMax - (gridV[r] + 0.5) * (erp.latMax - erp.latMin) / erp.height;
    if (std::fabs(latitude) >= 90.0) poleRows.push_back(int(r));
  }
  rays.resize(gridU.size() * gridV.size());
  for (size_t r = 0; r < gridV.size(); ++r) {
    const bool pole = std::find(poleRows.begin(), poleRows.end(), int(r)) != poleRows.end();
    for (size_t c = 0; c < gridU.size(); ++c) {
      // The wrap column looks along the first column's rays (the same samples, a turn on).
      const double u = erp.wraps() && c + 1 == gridU.size() ? gridU[0] : gridU[c];
      Vec3 ray = reference.rayCamera(u, gridV[r]);
      if (pole) ray = Vec3(0.0, ray.y < 0.0 ? -1.0 : 1.0, 0.0);  // our y points down: north is -y
      rays[r * gridU.size() + c] = ray;
    }
  }
}

void joinErpPoleRows(const std::vector<int>& poleRows, DepthMesh& mesh, std::vector<double>& inverseDistance) {
  std::vector<double> row;
  for (int r : poleRows) {
    const size_t first = size_t(r) * size_t(mesh.columns);
    row.clear();
    for (size_t i = first; i < first + size_t(mesh.columns); ++i)
      if (mesh.valid[i]) row.push_back(inverseDistance[i]);
    if (row.empty()) continue;
    std::nth_element(row.begin(), row.begin() + long(row.size() / 2), row.end());
    const double median = row[row.size() / 2];
    for (size_t i = first; i < first + size_t(mesh.columns); ++i)
      if (mesh.valid[i]) {
        inverseDistance[i] = median;
        mesh.vertices[i * 4 + 3] = float(median);
      }
  }
}

void referencePoint(const DepthMesh& mesh, const Camera& reference, size_t i, double point[4], double& u, double& v) {
  const float* vertex = &mesh.vertices[i * 4];
  if (reference.isEquirectangular()) {
    for (int k = 0; k < 4; ++k) point[k] = double(vertex[k]);
    u = mesh.gridU[i % size_t(mesh.columns)];
    v = mesh.gridV[i / size_t(mesh.columns)];
    return;
  }
  // (a u, a v, a, w): K^-1 (a u, a v, a) = w x_cam.
  const double a = double(vertex[2]);
  u = double(vertex[0]) / a;
  v = double(vertex[1]) / a;
  const Vec3 x = reference.pixelToCamera(u, v, a);
  point[0] = x.x;
  point[1] = x.y;
  point[2] = x.z;
  point[3] = double(vertex[3]);
}

namespace {

// Whether levels[3] is A sin(t) + B cos(t) + C of the curve through the first three (angles t, radians),
// within the rounding of all four (half a level each).
bool levelsFitSinusoid(const double t[4], const int levels[4]) {
  // The prediction is sum c_k levels[k] with c = M^-T e, M's rows (sin, cos, 1) of t_0..t_2 and e that
  // of t_3; angles taken from t_0 keep M well scaled.
  double m[3][3], e[3];
  for (int k = 0; k < 3; ++k) {
    m[k][0] = std::sin(t[k] - t[0]);
    m[k][1] = std::cos(t[k] - t[0]);
    m[k][2] = 1.0;
  }
  e[0] = std::sin(t[3] - t[0]);
  e[1] = std::cos(t[3] - t[0]);
  e[2] = 1.0;
  // Solve M^T c = e by Cramer's rule: (M^T)_{ij} = m[j][i].
  auto det = [](const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  double mt[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) mt[i][j] = m[j][i];
  const double d = det(mt);
  if (!(std::fabs(d) > 0.0)) return false;
  double predicted = 0.0, bound = 1.0;
  for (int k = 0; k < 3; ++k) {
    double replaced[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) replaced[i][j] = j == k ? e[i] : mt[i][j];
    const double c = det(replaced) / d;
    predicted += c * levels[k];
    bound += std::fabs(c);
  }
  return std::fabs(predicted - levels[3]) <= 0.5 * bound + 1e-9;
}

}  // namespace

bool erpEdgeOnPlane(const Camera& reference, const std::vector<double>& gridU, const std::vector<double>& gridV,
                    const std::vector<int>& poleRows, int row, int column, int dr, int dc, const int line[6]) {
  if (dr != 0 && dc != 0) return false;  // a diagonal: both angles vary, four levels fit any plane
  const EquirectangularRange& e = reference.erp;
  const double radians = M_PI / 180.0;
  double angle[6];
  bool usable[6];
  for (int k = -2; k <= 3; ++k) {
    const int r = row + k * dr, c = column + k * dc;
    usable[k + 2] = line[k + 2] != std::numeric_limits<int>::min() &&
                    std::find(poleRows.begin(), poleRows.end(), r) == poleRows.end();
    if (!usable[k + 2]) continue;
    angle[k + 2] = dr != 0 ? (e.latMax - (gridV[size_t(r)] + 0.5) * (e.latMax - e.latMin) / e.height) * radians
                           : (e.lonMax - (gridU[size_t(c)] + 0.5) * (e.lonMax - e.lonMin) / e.width) * radians;
  }
  for (int first = 0; first <= 2; ++first)  // windows line[first .. first + 3], all hold the edge
    if (usable[first] && usable[first + 1] && usable[first + 2] && usable[first + 3] &&
        levelsFitSinusoid(angle + first, line + first))
      return true;
  return false;
}

namespace {

constexpr int kMaxSplits = 6;          // an ERP triangle is split into four at most this many times
constexpr double kMaxBend = 0.5;       // virtual pixels an edge's ERP image may bend before a split
constexpr double kFarClipW = 1e30;     // clip w of a point at infinity (q = 0) in an ERP virtual camera

// A vertex on its way into an ERP virtual camera.
struct ErpVertex {
  double point[4];  // homogeneous virtual-camera point w (x, 1)
  double x = 0, y = 0, q = 0;  // virtual pixel position and inverse distance
  double u = 0, v = 0;         // reference pixel
  bool axis = false;           // on the virtual pole axis: no longitude
  int64_t index = -1;          // the output vertex it already is (unshifted), -1 none
};

class ErpProjector {
public:
  ErpProjector(const Camera& camera, const RenderGrid& grid, ProjectedMesh& out)
      : camera_(camera), out_(out), width_(grid.width), height_(grid.height) {
    const EquirectangularRange& e = camera.erp;
    turn_ = width_ * 360.0 / (e.lonMax - e.lonMin);
    wraps_ = e.wraps();
    const double rowsPerDegree = height_ / (e.latMax - e.latMin);
    northRow_ = (e.latMax - 90.0) * rowsPerDegree - 0.5;
    southRow_ = (e.latMax + 90.0) * rowsPerDegree - 0.5;
  }

  // Fills x, y, q and axis from `point`; false at the camera centre itself.
  bool place(ErpVertex& p) const {
    const Vec3 d(p.point[0], p.point[1], p.point[2]);
    const double length = norm(d);
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    p.q = p.point[3] / length;
    p.axis = !(std::hypot(d.x, d.z) > 1e-12 * length);
    if (!camera_.cameraToPixel(d, p.x, p.y)) return false;
    return std::isfinite(p.q);
  }

  void setPlanes(const InverseDepthRange& planes) {
    depthA_ = (planes.hi + planes.lo) / (planes.hi - planes.lo);
    depthB_ = -2.0 / (planes.hi - planes.lo);
  }

  // Appends an output vertex at (x, y) with p's attributes (q at the pole rows: `q`).
  uint32_t emit(const ErpVertex& p, double x, double y) {
    const double w = p.q > 1.0 / kFarClipW ? 1.0 / p.q : kFarClipW;
    const double ndcX = 2.0 * (x + 0.5) / width_ - 1.0, ndcY = 2.0 * (y + 0.5) / height_ - 1.0;
    const double ndcZ = depthA_ + depthB_ * p.q;
    out_.positions.insert(out_.positions.end(), {float(ndcX * w), float(ndcY * w), float(ndcZ * w), float(w)});
    out_.attributes.insert(out_.attributes.end(), {float(p.u), float(p.v), float(p.q), 1.0f});
    return uint32_t(out_.vertexCount() - 1);
  }
  uint32_t vertexIndex(ErpVertex& p) {
    if (p.index < 0) p.index = emit(p, p.x, p.y);
    return uint32_t(p.index);
  }

  // The triangle, split while its ERP image bends (the header of MeshErp.h).
  void triangle(ErpVertex& a, ErpVertex& b, ErpVertex& c, int splits) {
    const int axes = int(a.axis) + int(b.axis) + int(c.axis);
    if (axes >= 2) return;  // two vertices on the pole axis: a triangle seen edge-on through the pole
    if (splits < kMaxSplits) {
      ErpVertex ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      const double bend = std::max({bent(a, b, ab), bent(b, c, bc), bent(c, a, ca)});
      if (bend > kMaxBend) {
        triangle(a, ab, ca, splits + 1);
        triangle(ab, b, bc, splits + 1);
        triangle(ca, bc, c, splits + 1);
        triangle(ab, bc, ca, splits + 1);
        return;
      }
    }
    if (axes == 1) {
      ErpVertex* ring[3] = {&a, &b, &c};
      int k = 0;
      while (!ring[k]->axis) ++k;
      poleSegment(*ring[k], *ring[(k + 1) % 3], *ring[(k + 2) % 3]);
      return;
    }
    const double xb = a.x + unwrap(b.x - a.x), xc = a.x + unwrap(c.x - a.x);
    const double winding = unwrap(b.x - a.x) + unwrap(c.x - b.x) + unwrap(a.x - c.x);
    if (std::fabs(winding) > 0.5 * turn_) return poleCap(a, b, c);
    const double lo = std::min({a.x, xb, xc}), hi = std::max({a.x, xb, xc});
    for (double shift : shifts(lo, hi)) {
      if (shift == 0.0 && xb == b.x && xc == c.x) {
        out_.triangles.insert(out_.triangles.end(), {vertexIndex(a), vertexIndex(b), vertexIndex(c)});
        continue;
      }
      out_.triangles.insert(out_.triangles.end(),
                            {emit(a, a.x + shift, a.y), emit(b, xb + shift, b.y), emit(c, xc + shift, c.y)});
    }
  }

private:
  double unwrap(double dx) const { return dx - turn_ * std::round(dx / turn_); }

  // The copies of an x range [lo, hi] that overlap the picture: shifted by whole turns.
  std::vector<double> shifts(double lo, double hi) const {
    std::vector<double> list{0.0};
    if (!wraps_) return list;
    if (lo < -0.5) list.push_back(turn_);
    if (hi > width_ - 0.5) list.push_back(-turn_);
    return list;
  }

  ErpVertex middle(const ErpVertex& a, const ErpVertex& b) const {
    ErpVertex m;
    for (int k = 0; k < 4; ++k) m.point[k] = 0.5 * (a.point[k] + b.point[k]);
    m.u = 0.5 * (a.u + b.u);
    m.v = 0.5 * (a.v + b.v);
    if (!place(m)) m.axis = true;  // through the centre: split as far as allowed
    return m;
  }

  // How far the ERP image of the edge's 3D midpoint lies from the middle of its projected ends.
  double bent(const ErpVertex& a, const ErpVertex& b, const ErpVertex& m) const {
    if (a.axis || b.axis || m.axis) return HUGE_VAL;
    const double xb = a.x + unwrap(b.x - a.x), xm = a.x + unwrap(m.x - a.x);
    return std::hypot(xm - 0.5 * (a.x + xb), m.y - 0.5 * (a.y + b.y));
  }

  double poleRow(const ErpVertex& around) const { return around.point[1] < 0.0 ? northRow_ : southRow_; }

  // Pole vertex p between b and c: the quad b, c and their longitudes on the pole row.
  void poleSegment(const ErpVertex& p, const ErpVertex& b, const ErpVertex& c) {
    const double xc = b.x + unwrap(c.x - b.x), row = poleRow(p);
    ErpVertex bp = b, cp = c;
    bp.q = cp.q = p.q;
    bp.v = cp.v = p.v;
    for (double shift : shifts(std::min(b.x, xc), std::max(b.x, xc))) {
      const uint32_t i0 = emit(b, b.x + shift, b.y), i1 = emit(c, xc + shift, c.y);
      const uint32_t i2 = emit(cp, xc + shift, row), i3 = emit(bp, b.x + shift, row);
      out_.triangles.insert(out_.triangles.end(), {i0, i1, i2, i0, i2, i3});
    }
  }

  // A triangle around the pole axis: the band from each edge to the pole row, a whole turn.
  void poleCap(const ErpVertex& a, const ErpVertex& b, const ErpVertex& c) {
    const ErpVertex* ring[4] = {&a, &b, &c, &a};
    const double row = (a.point[1] / norm(Vec3(a.point[0], a.point[1], a.point[2])) +
                        b.point[1] / norm(Vec3(b.point[0], b.point[1], b.point[2])) +
                        c.point[1] / norm(Vec3(c.point[0], c.point[1], c.point[2]))) < 0.0
                           ? northRow_
                           : southRow_;
    double x = a.x;
    for (int k = 0; k < 3; ++k) {
      const ErpVertex &p = *ring[k], &n = *ring[k + 1];
      const double xn = x + unwrap(n.x - p.x);
      for (double shift : {-turn_, 0.0, turn_}) {
        const uint32_t i0 = emit(p, x + shift, p.y), i1 = emit(n, xn + shift, n.y);
        const uint32_t i2 = emit(n, xn + shift, row), i3 = emit(p, x + shift, row);
        out_.triangles.insert(out_.triangles.end(), {i0, i1, i2, i0, i2, i3});
      }
      x = xn;
    }
  }

  const Camera& camera_;
  ProjectedMesh& out_;
  int width_, height_;
  double turn_ = 0;  // pixels in 360 degrees of longitude
  bool wraps_ = false;
  double northRow_ = 0, southRow_ = 0;  // pixel rows of latitudes +90 and -90
  double depthA_ = 0, depthB_ = 0;      // z_ndc = A + B q
};

}  // namespace

namespace {

// Into a pinhole virtual camera: P applied in double to every usable vertex; q = w / w_clip as the
// pinhole pass has it. The triangles, points and orphans are the mesh's own.
void clipForPinhole(const DepthMesh& mesh, const std::vector<ErpVertex>& vertices, const std::vector<uint8_t>& usable,
                    const Mat4& projection, ProjectedMesh& out) {
  const size_t n = mesh.vertexCount();
  out.positions.assign(n * 4, 0.0f);
  out.attributes.assign(n * 4, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    if (!usable[i]) continue;
    const ErpVertex& p = vertices[i];
    float* position = &out.positions[i * 4];
    for (int r = 0; r < 4; ++r) {
      const double* row = projection.m[r];
      position[r] = float(row[0] * p.point[0] + row[1] * p.point[1] + row[2] * p.point[2] + row[3] * p.point[3]);
    }
    float* attribute = &out.attributes[i * 4];
    attribute[0] = float(p.u);
    attribute[1] = float(p.v);
    attribute[2] = float(p.point[3]);
    attribute[3] = position[3];
  }
  out.triangles = mesh.triangles;
  out.points = mesh.points;
  out.farthestOrphans = mesh.farthestOrphans;
}

// Into an ERP virtual camera: triangle by triangle (ErpProjector), then the points.
void projectForErp(const DepthMesh& mesh, std::vector<ErpVertex>& vertices, const std::vector<uint8_t>& usable,
                   ErpProjector& projector, ProjectedMesh& out) {
  out.positions.reserve(mesh.vertexCount() * 4);
  out.attributes.reserve(mesh.vertexCount() * 4);
  out.triangles.reserve(mesh.triangles.size());
  for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const uint32_t a = mesh.triangles[t], b = mesh.triangles[t + 1], c = mesh.triangles[t + 2];
    if (usable[a] && usable[b] && usable[c]) projector.triangle(vertices[a], vertices[b], vertices[c], 0);
  }
  for (uint32_t i : mesh.points)
    if (usable[i] && !vertices[i].axis) out.points.push_back(projector.vertexIndex(vertices[i]));
  for (uint32_t i : mesh.farthestOrphans)
    if (usable[i] && !vertices[i].axis) out.farthestOrphans.push_back(projector.vertexIndex(vertices[i]));
}

}  // namespace

bool projectMesh(const DepthMesh& mesh, const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid,
                 ProjectedMesh& out) {
  VS_CHECK(mesh.vertices.size() == mesh.vertexCount() * 4);
  out.positions.clear();
  out.attributes.clear();
  out.triangles.clear();
  out.points.clear();
  out.farthestOrphans.clear();
  out.mesh = &mesh;
  const size_t n = mesh.vertexCount();
  const RelativePose pose = relativePose(reference, virtualCamera);
  // Every valid vertex in virtual camera coordinates, homogeneous: (R x + t w, w) of x = (x, y, z) w,
  // and its q; the range of q gives the depth-buffer planes.
  std::vector<ErpVertex> vertices(n);
  std::vector<uint8_t> usable(n, 0);
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  const bool erpVirtual = virtualCamera.isEquirectangular();
  ErpProjector projector(virtualCamera, grid, out);
  for (size_t i = 0; i < n; ++i) {
    if (!mesh.valid[i]) continue;
    ErpVertex& p = vertices[i];
    double x[4];
    referencePoint(mesh, reference, i, x, p.u, p.v);
    const Vec3 moved = pose.R * Vec3(x[0], x[1], x[2]) + pose.t * x[3];
    p.point[0] = moved.x;
    p.point[1] = moved.y;
    p.point[2] = moved.z;
    p.point[3] = x[3];
    if (erpVirtual) {
      if (!projector.place(p)) continue;
    } else {
      if (!(moved.z > 0.0)) {
        usable[i] = 1;  // behind the pinhole camera: OpenGL clips it; no q of its own
        continue;
      }
      p.q = x[3] / moved.z;
    }
    usable[i] = 1;
    lo = std::min(lo, p.q);
    hi = std::max(hi, p.q);
  }
  if (lo > hi) return false;
  const InverseDepthRange planes = clipPlanes({lo, hi});
  if (!erpVirtual) {
    clipForPinhole(mesh, vertices, usable, projectionMatrix(grid, planes), out);
    return true;
  }
  projector.setPlanes(planes);
  projectForErp(mesh, vertices, usable, projector, out);
  return true;
}

}  // namespace vs
