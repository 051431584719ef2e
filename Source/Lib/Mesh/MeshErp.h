#pragma once
// MeshRender with equirectangular (ERP) cameras (doc/meshrender.md, "Equirectangular cameras").
//
// The mesh of an ERP depth map (DepthMeshBuilder calls the first three functions for an ERP reference):
// - vertices sit on the camera's own rays (Camera::rayCamera, MPEG's axes); the depth of an ERP map is
//   the distance along the ray, so a vertex is stored as (ray, 1 / distance): w (x_cam, 1) with
//   x_cam = distance * ray, the homogeneous reference-camera point that a pinhole mesh's
//   diag(K^-1, 1) (a u, a v, a, w) also is. Its reference pixel is its grid position (DepthMesh::gridU, gridV).
// - a full-circle reference (360 degrees of longitude) has no half-pixel border columns: its last
//   grid column is the first pixel column again, one whole turn on (u = W, reading pixel 0), so the
//   quads between the last and the first pixel columns join across the wrap, and are dropped there, like
//   any other quad, where the depth is not continuous (MeshDiscontinuityThreshold on the distances).
// - a grid row at a pole (latitude +-90, the half-pixel border row of a range that reaches the pole)
//   is one point: every vertex of it gets the pole's ray and one distance, the median of the row's
//   valid vertices. The quads between it and the first pixel row are then a fan of triangles around
//   the pole plus triangles of zero area; no needle runs from the pole along a ray.
// - the depth-level rule for planes seen at a grazing angle (levels affine on a plane) and the adaptive
//   merge (MeshMaxError) assume a pinhole camera: both are off when either camera is ERP.
//
// Rendering (projectMesh): with an ERP camera on either side, the mesh's vertices are taken into the
// virtual camera's clip coordinates on the CPU, in double, and drawn by the renderer's projected pass
// (GlMeshRenderer::renderProjected):
// - a pinhole virtual camera: clip = P (MeshProjection.h) applied to the vertex in virtual camera
//   coordinates; OpenGL interpolates and clips as for a pinhole reference;
// - an ERP virtual camera: longitude and latitude of the vertex's direction in the virtual camera
//   (Camera::cameraToPixel, MPEG's axes), q = 1 / distance, depth test on q; clip w = distance so that
//   OpenGL interpolates the reference position as along the 3D triangle. Per triangle: the longitudes
//   are unwrapped around its first vertex; a triangle that crosses the picture's wrap is drawn again
//   shifted by a whole turn; a triangle whose ERP image bends by more than half a pixel (an edge's 3D
//   midpoint against the midpoint of its projected ends) is split into four, up to 6 times; a triangle
//   around a pole of the virtual camera is drawn as the band between its edges and the pole row; a
//   vertex on the pole axis (no longitude) is drawn as a segment of the pole row between its
//   neighbours' longitudes.
#include <cstdint>
#include <vector>

#include "Common/Camera.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/MeshProjection.h"
#include "Synth/Interpolation.h"

namespace vs {

// The grid of an ERP reference's mesh, given DepthMeshBuilder's pinhole grid (columns -0.5, 0, s, ...,
// W-1, W-0.5, rows likewise; `pixelU`: the depth sample each column reads): a full circle's border
// columns become one wrap column u = W reading pixel 0. `rays`: the unit ray of each grid vertex
// (row-major) in the reference camera's coordinates, the wrap column's the first column's, a pole row's
// the pole's exactly; `poleRows`: the grid rows on a pole (latitude +-90).
void erpMeshGrid(const Camera& reference, std::vector<double>& gridU, std::vector<int>& pixelU,
                 const std::vector<double>& gridV, std::vector<Vec3>& rays, std::vector<int>& poleRows);
// Makes each pole row one point (the header): its valid vertices get the median of their inverse
// distances (`inverseDistance`, updated with the vertices).
void joinErpPoleRows(const std::vector<int>& poleRows, DepthMesh& mesh, std::vector<double>& inverseDistance);

// The grazing-plane rule for an ERP reference (DepthMesh.cpp's planar(), whose pinhole form assumes levels
// affine in the image): on a plane n . x = c a depth level is affine in 1 / d = n . ray / c, so along a
// grid row (latitude fixed) the levels are A sin(lon) + B cos(lon) + C, and along a grid column
// (longitude fixed) A sin(lat) + B cos(lat) + C. The edge from grid vertex (row, column) one step along
// (dr, dc) lies on a plane when four valid vertices in a row on its line that hold it (`line`: levels
// at k = -2 .. 3 steps, INT_MIN where none) fit that form within the rounding of the levels (the
// fourth level predicted from three, against half a level on each). Diagonal edges (both angles
// vary) and pole rows are not checked here.
bool erpEdgeOnPlane(const Camera& reference, const std::vector<double>& gridU, const std::vector<double>& gridV,
                    const std::vector<int>& poleRows, int row, int column, int dr, int dc, const int line[6]);

// Whether a reference/virtual pair takes the projected pass (either camera is ERP).
inline bool projectedPass(const Camera& reference, const Camera& virtualCamera) {
  return reference.isEquirectangular() || virtualCamera.isEquirectangular();
}

// How a reference's texture continues beyond its edges for the colour look-up
// (GlMeshRenderer::setReferenceSphere), as ViewSyn's warps read it (Synth/Warp.cpp): a full-circle ERP
// camera round its wrap, and across a pole its picture reaches; any other camera not at all.
inline SphereEdges meshReferenceSphere(const Camera& reference) {
  SphereEdges edges;
  edges.wrap = reference.isEquirectangular() && reference.erp.wraps();
  edges.north = edges.wrap && reference.erp.latMax >= 90.0;
  edges.south = edges.wrap && reference.erp.latMin <= -90.0;
  return edges;
}

// A mesh in the virtual camera's clip coordinates, for GlMeshRenderer::renderProjected. Per vertex:
// the clip position (x, y, z, w) and (u, v, n, d): the reference pixel it shows and its inverse virtual
// depth q = n / d, each interpolated by OpenGL with perspective correction.
struct ProjectedMesh {
  std::vector<float> positions;   // 4 floats a vertex
  std::vector<float> attributes;  // 4 floats a vertex
  std::vector<uint32_t> triangles, points, farthestOrphans;  // as DepthMesh's, into these vertices
  const DepthMesh* mesh = nullptr;  // the mesh it came from (its edge flags)
  size_t vertexCount() const { return positions.size() / 4; }
};

// The homogeneous point w (x_cam, 1) of mesh vertex i in the reference camera's coordinates, and its
// reference pixel.
void referencePoint(const DepthMesh& mesh, const Camera& reference, size_t i, double point[4], double& u, double& v);

// Projects `mesh` of `reference` into `virtualCamera`'s luma grid (the header); the depth-buffer planes
// come from the projected vertices' q. Returns false when no vertex is in front of the virtual camera.
bool projectMesh(const DepthMesh& mesh, const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid,
                 ProjectedMesh& out);

}  // namespace vs
