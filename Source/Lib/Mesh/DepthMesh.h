#pragma once
// A triangle mesh from one reference view's depth map (doc/meshrender.md, "Mesh from depth").
//
// Vertices form a grid over the reference picture: columns at u = -0.5, 0, s, 2s, ..., W-1, W-0.5
// (s = MeshGridStep; the last pixel column W-1 is always a vertex column even when s does not divide
// W-1), rows likewise. The half-pixel border vertices take the depth of the nearest pixel, so the mesh
// covers the whole picture area [-0.5, W-0.5] x [-0.5, H-0.5] that the reference camera saw, and the
// reference projected into itself is covered up to its border samples.
//
// A vertex is stored in homogeneous reference-pixel form (a u, a v, a, w): w = 1/Z of its depth level
// (Z as DepthType defines it) and a = w z_cam, so that K_ref^-1 (a u, a v, a) = w x_cam and the 4-vector
// is w (x_cam, 1). DepthType 0: a = 1. DepthType 1: a = (1 - w C_z) / D_z with C the camera centre and
// D = R^-1 K^-1 (u, v, 1) the world ray. The sign is normalised to w >= 0; a > 0 means the point is in
// front of the reference camera. w = 0 (Zfar = inf) is a point at infinity and needs no special case:
// OpenGL's clip-space w handles it (doc/meshrender.md, "Camera").
//
// Each grid quad gives two triangles, split along the diagonal whose ends have the closer depths (or the
// one that avoids the quad's only invalid vertex). A triangle is dropped when two of its vertices'
// camera depths differ by more than the threshold, 1 - z_min / z_max > MeshDiscontinuityThreshold,
// unless that edge continues a plane: with DepthType 0, when the edge belongs to four vertices in a
// row on its grid line whose depth levels step evenly (within 2 levels, the rounding of the levels).
// A plane seen at a grazing angle, like a floor towards the horizon, steps by a large relative depth
// from sample to sample and would otherwise lose all its triangles. Vertices at MissingDepthLevel,
// behind the camera, or whose ray misses a DepthType 1 plane are invalid and drop every triangle they
// belong to.
//
// The vertices on the border of what is kept (those of a kept triangle that also belong to a dropped
// one) are listed as points too, and drawn as one-pixel points after the triangles. A mesh ends at
// its border vertices, that is at pixel centres, half a pixel short of where the reference pixel's
// area ends; rendered as it is, a silhouette pixel whose centre falls on the mesh border is covered or
// not depending on the rasteriser's tie rule (a reference view rendered into itself would lose about
// half of them). The point covers the pixel nearest to the projected vertex, as ViewSyn's point splat
// does. A point's fragments read the texture where their own pixel centre looks at the point's depth
// (GlMeshRenderer), so a reference rendered into itself is reproduced exactly.
// Vertices without any kept triangle (orphans: samples of a curved surface seen at a grazing angle,
// thin structures, noise) are drawn as points too, unless no valid neighbour among the 8 around is
// farther: such a sample is a speck of background seen through a gap of the depth map (or a noisy
// one) and, drawn, would show through in every disocclusion (Cloth2 of Middlebury 2006: -1.6 dB).
// Those locally farthest orphans are listed separately (farthestOrphans): the renderer draws them only
// into a pixel that nothing else of their view covers and that is not part of a larger hole, which
// gives a reference rendered into itself back exactly without letting them into disocclusions.
//
// An equirectangular (ERP) reference's mesh differs where Mesh/MeshErp.h says: vertices (ray, 1 / distance)
// on the camera's rays, a full circle's wrap column instead of the border columns, pole rows joined
// into one point, the grazing-plane rule in its ERP form, no adaptive merge.
//
// Adaptive mesh (MeshMaxError, doc/meshrender.md "Adaptive mesh"): given how far a point moves in the
// virtual camera per unit of its inverse depth (a DisplacementRate, which depends on the camera model),
// aligned square blocks of 2^k x 2^k grid cells whose every triangle is kept and whose every vertex lies
// within the bound of the two triangles through the block's corners are merged (bottom-up, as a
// region quadtree), at most 128 cells wide; where a block does not merge, two of its four quarters side by
// side (or one above the other) that did still merge as a 2:1 rectangle if it passes the same test.
// A merged block or rectangle is drawn as two triangles, or, where smaller
// neighbours put vertices on its sides, as a triangulation of each of the two tested triangles through
// those vertices (n - 2 triangles for n vertices on the block's outline, each inside one tested
// triangle), so the mesh has no T-junctions and no cracks. A cell with a dropped triangle (a depth edge) or an invalid vertex is
// never merged: it stays as it is, and the merged blocks beside it pass through all its vertices, so
// the mesh's outline keeps full resolution.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "Common/Camera.h"
#include "Common/Depth.h"
#include "Common/Frame.h"

namespace vs {

struct MeshOptions {
  int depthType = 0;                     // DepthType: 0 camera z, 1 world z
  int gridStep = 1;                      // MeshGridStep: vertex spacing in pixels
  double discontinuityThreshold = 0.02;  // MeshDiscontinuityThreshold: relative depth step that drops a triangle
  int missingDepthLevel = -1;            // MissingDepthLevel: vertices at this level are dropped; -1 off
  double maxError = 2.0;                 // MeshMaxError: virtual-camera pixels a merged block may move a sample
  // MeshMaxColourError: with the reference luma, a merged block may be off at a sample only as far as
  // keeps the colour a virtual pixel shows there within this many sample values (the luma step from
  // the sample to its neighbour along the reference shift, ReferenceShift, times the shift); 0: off.
  double maxColourError = 2.6;
};

// A camera-dependent quantity of a reference pixel (u, v) at inverse camera depth q that the adaptive
// mesh asks for at every tested vertex or block corner: held either as the pinhole camera's terms H, e
// (a point at reference pixel (u, v) with inverse depth q sits at h = H (u, v, 1) + q e in the virtual
// camera, MeshProjection.h), computed inline by `Formula::pinhole(H, e, ...)`, or as any other function
// of the same signature (`Formula::Signature`; the tests pass such). Empty by default.
template <typename Formula>
class PinholeTermsOrFunction {
public:
  using Function = std::function<typename Formula::Signature>;

  PinholeTermsOrFunction() = default;
  template <typename F, typename = std::enable_if_t<!std::is_same_v<std::decay_t<F>, PinholeTermsOrFunction> &&
                                                    Formula::template invocable<F>>>
  PinholeTermsOrFunction(F function) : general_(std::move(function)) {}
  static PinholeTermsOrFunction pinhole(const Mat3& H, const Vec3& e) {
    PinholeTermsOrFunction terms;
    terms.pinhole_ = true;
    terms.H_ = H;
    terms.e_ = e;
    return terms;
  }
  explicit operator bool() const { return pinhole_ || bool(general_); }
  // Whether the value is the same, to the bit, at every reference pixel (u, v) with |u|, |v| <= 1e9 and
  // every q with |q| <= qLimit (written here): so for pinhole terms whose H has the last row (0, 0, c) and
  // whose e_z is 0 (the virtual image plane parallel to the reference's, no move along the optical
  // axis: rectified or parallel cameras). There h_z = c whatever (u, v, q) (H's zeros make (0 u + 0 v) + c
  // = c, and q e_z = 0), and each formula adds to its terms in c only products h_x 0, h_y 0, which are
  // zeros while h_x, h_y are finite; qLimit keeps them finite. The adaptive mesh then computes it once.
  bool uniform(double& qLimit) const {
    qLimit = 0.0;
    if (!pinhole_ || !(H_[2][0] == 0.0 && H_[2][1] == 0.0 && e_.z == 0.0)) return false;
    double largest = 0.0;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(H_[r][k])) return false;
        largest = std::max(largest, std::fabs(H_[r][k]));
      }
    if (!std::isfinite(e_.x) || !std::isfinite(e_.y) || !(largest < 1e280)) return false;
    // |h_x| <= largest (|u| + |v| + 1) + |q| |e_x| stays far below the largest double.
    qLimit = 1e290 / (1.0 + std::fabs(e_.x) + std::fabs(e_.y));
    return true;
  }
  template <typename... Arguments>
  auto operator()(Arguments&&... arguments) const {
    if (!pinhole_) return general_(std::forward<Arguments>(arguments)...);
    return Formula::pinhole(H_, e_, std::forward<Arguments>(arguments)...);
  }

private:
  bool pinhole_ = false;
  Mat3 H_;
  Vec3 e_;
  Function general_;
};

// How far, in virtual-camera pixels, a surface point seen at reference pixel (u, v) with inverse camera
// depth q (1 / z_cam) moves in the virtual camera per unit of q: |d pixel / d q|. Infinite (or NaN)
// where the point is not in front of the virtual camera. The adaptive mesh turns MeshMaxError into a
// tolerance in q with it; each camera model supplies its own (pinholeDisplacementRate, MeshProjection.h).
struct DisplacementRateFormula {
  using Signature = double(double u, double v, double q);
  template <typename F>
  static constexpr bool invocable = std::is_invocable_r_v<double, const F&, double, double, double>;
  // h = H (u, v, 1) + q e: d pixel / d q = (e_xy h_z - h_xy e_z) / h_z^2.
  static double pinhole(const Mat3& H, const Vec3& e, double u, double v, double q) {
    const Vec3 h = H * Vec3(u, v, 1.0) + q * e;
    if (!(h.z > 0.0)) return std::numeric_limits<double>::infinity();
    const double dx = (e.x * h.z - h.x * e.z) / (h.z * h.z), dy = (e.y * h.z - h.y * e.z) / (h.z * h.z);
    return std::sqrt(dx * dx + dy * dy);
  }
};
using DisplacementRate = PinholeTermsOrFunction<DisplacementRateFormula>;

// How the texture seen in the virtual camera moves with a surface drawn off in q: the virtual pixel that
// truly shows reference pixel (u, v) (inverse depth q) shows reference position (u, v) - dq (du, dv)
// when the surface there is drawn at q + dq (to first order, the surface taken as facing the reference
// camera). Writes (du, dv), in reference pixels per unit of q, along the epipolar line of (u, v); false
// where the point is not in front of the virtual camera. MeshMaxColourError turns the luma step along it
// into a tolerance in q (pinholeReferenceShift, MeshProjection.h).
struct ReferenceShiftFormula {
  using Signature = bool(double u, double v, double q, double& du, double& dv);
  template <typename F>
  static constexpr bool invocable = std::is_invocable_r_v<bool, const F&, double, double, double, double&, double&>;
  // h = H (u, v, 1) + q e; (du, dv) = J^-1 (d pixel / d q) with J = d pixel / d(u, v) (MeshProjection.h).
  static bool pinhole(const Mat3& H, const Vec3& e, double u, double v, double q, double& du, double& dv) {
    const Vec3 h = H * Vec3(u, v, 1.0) + q * e;
    if (!(h.z > 0.0)) return false;
    // d pixel / d u, d pixel / d v and d pixel / d q are each (b_xy h_z - h_xy b_z) / h_z^2 for their
    // column b; the common 1 / h_z^2 cancels in J^-1 (d pixel / d q), so it is left out.
    auto derivative = [&h](const Vec3& b, double& x, double& y) {
      x = b.x * h.z - h.x * b.z;
      y = b.y * h.z - h.y * b.z;
    };
    double xu, yu, xv, yv, xq, yq;
    derivative(Vec3(H[0][0], H[1][0], H[2][0]), xu, yu);
    derivative(Vec3(H[0][1], H[1][1], H[2][1]), xv, yv);
    derivative(e, xq, yq);
    const double det = xu * yv - xv * yu;
    if (!(std::fabs(det) > 0.0)) return false;
    const double inverse = 1.0 / det;
    du = (yv * xq - xv * yq) * inverse;
    dv = (xu * yq - yu * xq) * inverse;
    return std::isfinite(du) && std::isfinite(dv);
  }
};
using ReferenceShift = PinholeTermsOrFunction<ReferenceShiftFormula>;

struct DepthMesh {
  int columns = 0, rows = 0;           // vertex grid size
  int gridStep = 1;                    // MeshGridStep: spacing of the inner grid lines (gridU, gridV)
  std::vector<double> gridU, gridV;    // reference pixel position of each grid column and row
  std::vector<float> vertices;         // 4 floats a vertex, row-major over the grid: (a u, a v, a, w)
  std::vector<uint8_t> boundary;       // 1 a vertex: 1 where it belongs to a dropped triangle
  // Per grid cell, how its quad was split and which of its triangles were kept (DepthMesh.cpp's cell
  // code); its low 3 bits are 1 where the split runs from (c+1, r) to (c, r+1), otherwise from corner
  // (c, r) to (c+1, r+1). With `boundary`, it tells whether the grid triangle under a reference
  // position touches a dropped one (edgeAt), whatever triangles the adaptive mesh drew there.
  std::vector<uint8_t> cellSplit;
  std::vector<uint8_t> valid;            // 1 a vertex: a finite point in front of the reference camera
  std::vector<uint32_t> triangles;     // 3 vertex indices a triangle
  std::vector<uint32_t> points;        // border vertices of kept triangles and orphans, drawn as points
  std::vector<uint32_t> farthestOrphans;  // locally farthest orphans: drawn only into their own lone hole
  size_t droppedTriangles = 0;         // triangles left out (discontinuity or invalid vertex)
  size_t gridTriangles = 0;            // triangles kept before the adaptive merge (one grid quad: 2)

  size_t vertexCount() const { return size_t(columns) * size_t(rows); }
  // Whether the grid triangle that holds reference position (u, v) has a vertex on a dropped triangle
  // with a weight above 0 at (u, v): the edge flag of a sample drawn from a triangle (at a vertex
  // itself, only that vertex counts). Positions outside the grid take the nearest cell.
  bool edgeAt(double u, double v) const;
  size_t triangleCount() const { return triangles.size() / 3; }
};

// The homogeneous vertex (a u, a v, a, w) of reference pixel (u, v) with depth value 1/Z = inverseZ
// (see the header comment). Returns false when it is not a usable point: inverseZ NaN, behind the
// reference camera, or a DepthType 1 ray parallel to the plane. `inverseCameraZ` is w / a = 1 / z_cam
// (0 at infinity).
bool referenceVertex(const Camera& reference, int depthType, double u, double v, double inverseZ, double vertex[4],
                     double& inverseCameraZ);

// The largest double x >= 0 with x * rate <= bound in double arithmetic (rate >= 0 finite, bound >= 0;
// -1 otherwise). The product rounds monotonically in x, so for every double e, NaN and infinities
// included, |e| * rate <= bound holds exactly when |e| <= largestFactorWithin(rate, bound): the merge's
// test of a vertex at the rate every vertex has (rectified cameras) without a multiplication.
double largestFactorWithin(double rate, double bound);

class DepthMeshBuilder {
public:
  // For depth maps of `width` x `height` samples with levels in `range`, seen by `reference`. Without
  // `rate` the mesh keeps every grid quad (no adaptive merge); without `shift` the merge has no colour
  // bound (MeshMaxColourError).
  DepthMeshBuilder(const Camera& reference, const DepthRange& range, int width, int height, const MeshOptions& options,
                   DisplacementRate rate = {}, ReferenceShift shift = {});

  // Builds the mesh of one depth map (luma of the depth file; its size must be width x height).
  // `luma`: the view's texture luma, for MeshMaxColourError (ignored when null or of another size).
  void build(const Plane& depth, DepthMesh& mesh, const Plane* luma = nullptr) const;

  const MeshOptions& options() const { return options_; }

private:
  // Writes the adaptive mesh's triangles (the header comment) from each grid cell's split and kept
  // triangles (cellCode, DepthMesh.cpp); false, with nothing written, when no block merges.
  bool merge(DepthMesh& mesh, const std::vector<double>& inverseCameraZ, const std::vector<uint8_t>& cellCode,
             const Plane* luma) const;

  Camera reference_;
  DisplacementRate rate_;
  ReferenceShift shift_;
  MeshOptions options_;
  int width_, height_;
  std::vector<double> inverseZ_;     // per depth level; NaN for MissingDepthLevel
  std::vector<double> gridU_, gridV_;
  std::vector<int> pixelU_, pixelV_;  // depth sample each grid column and row reads
  std::vector<double> worldRayZ_;     // DepthType 1: D_z of each grid vertex
  std::vector<Vec3> erpRays_;         // ERP reference: the unit ray of each grid vertex (MeshErp.h)
  std::vector<int> erpPoleRows_;      // ERP reference: grid rows on a pole
};

}  // namespace vs
