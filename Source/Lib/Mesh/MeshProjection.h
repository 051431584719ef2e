#pragma once
// MeshRender's OpenGL camera (derivation in doc/meshrender.md, "Camera"). One 4x4 matrix, composed in
// double and uploaded as float, takes a mesh vertex (a u, a v, a, w) of a reference view (DepthMesh.h)
// to clip coordinates of a pixel grid of the virtual camera:
//
//   clip = P(K_grid, W, H, near, far) * [R t; 0 1] * diag(K_ref^-1, 1) * vertex
//
// [R t] is relativePose(reference, virtual): the centre difference is taken before anything is
// rotated, so large world translations cancel in double before the float upload. P is the pinhole K
// written for OpenGL: with the viewport (0, 0, W, H) a point that the pinhole model puts at pixel
// (u, v) lands at window position (u + 0.5, v + 0.5), the centre of fragment (u, v):
//
//   row 0 = (2/W) K_0 + (1/W - 1) K_2        x_ndc = 2 (u + 0.5) / W - 1
//   row 1 = (2/H) K_1 + (1/H - 1) K_2        y_ndc = 2 (v + 0.5) / H - 1   (no flip: see below)
//   row 2 = A K_2 + B e_w                    z_ndc = A + B q, q = 1 / z_virtual
//   row 3 = K_2                              w_clip = z_virtual (times the vertex's w)
//
// (K_r is row r of K, e_w picks the vertex's homogeneous weight.) Image row v = 0 goes to the bottom
// of the framebuffer, which is where glReadPixels starts, and row 0 of an uploaded texture is texel
// row 0: image, framebuffer memory and texture memory share one row order, so nothing is flipped,
// neither on read-back nor on texturing. The picture is upside down only to someone who displays the
// framebuffer as OpenGL's y-up convention expects; triangle winding is irrelevant (no culling).
//
// Depth: z_ndc is affine in inverse depth q, from -1 at q = near (largest q) to +1 at q = far; far may be
// 0 (Zfar = inf) or negative, so points at infinity are never clipped by the far plane.
#include "Common/Camera.h"
#include "Common/Depth.h"
#include "Common/Frame.h"
#include "Mesh/DepthMesh.h"

namespace vs {

struct Mat4 {
  double m[4][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
  static Mat4 identity();
};
Mat4 operator*(const Mat4& a, const Mat4& b);
// Column-major floats for glUniformMatrix4fv.
void toGlMatrix(const Mat4& a, float out[16]);

// A pixel grid rendered into: width x height samples whose integer positions are sample centres; K
// maps virtual camera coordinates to this grid's pixel positions.
struct RenderGrid {
  int width = 0;
  int height = 0;
  Mat3 K = Mat3::identity();
};

// The virtual camera's luma grid.
RenderGrid lumaGrid(const Camera& camera, int width, int height);
// Its chroma grid: 4:2:0 chroma sample (i, j) sits at luma position (2i + 0.5, 2j + 0.5), so the grid's
// K is S K with S = [1/2 0 -1/4; 0 1/2 -1/4; 0 0 1]; 4:4:4 is the luma grid. Not for 4:0:0.
RenderGrid chromaGrid(const Camera& camera, int lumaWidth, int lumaHeight, ChromaFormat format);

// Inverse virtual depth q = 1 / z_virtual: hi is the near plane, lo the far plane (0: infinity).
struct InverseDepthRange {
  double lo = 0.0;
  double hi = 0.0;
};

// The range of q that reference pixels in [-0.5, W-0.5] x [-0.5, H-0.5] with depth levels in `range`
// can have in the virtual camera. These points fill a convex body whose extreme q lie at the 4 picture
// corners at the nearest and the farthest level (doc/meshrender.md, "Near and far"). Returns false
// when the body is not bounded in q: part of it lies beside or behind the virtual camera, or a corner
// is not in front of the reference camera.
bool sceneInverseDepthRange(const Camera& reference, const DepthRange& range, int depthType, int width, int height,
                            const Camera& virtualCamera, InverseDepthRange& out);
// The range of q over the mesh's valid vertices in front of the virtual camera ({0, 0} when none is).
InverseDepthRange meshInverseDepthRange(const DepthMesh& mesh, const Camera& reference, const Camera& virtualCamera);
// The depth-buffer planes for a range: widened by 5 % of its span on each side (and never empty).
InverseDepthRange clipPlanes(const InverseDepthRange& range);

// diag(K_ref^-1, 1) followed by [R t; 0 1]: mesh vertex -> w (x_virtual, 1).
Mat4 referenceToVirtualMatrix(const Camera& reference, const Camera& virtualCamera);
// P above, for `grid` and the depth-buffer planes `planes` (from clipPlanes).
Mat4 projectionMatrix(const RenderGrid& grid, const InverseDepthRange& planes);
// projectionMatrix * referenceToVirtualMatrix.
Mat4 meshClipMatrix(const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid,
                    const InverseDepthRange& planes);

// The pinhole camera's DisplacementRate (DepthMesh.h) for `grid`'s pixels: a point at reference pixel
// (u, v) with inverse camera depth q sits at h = H p + q e in the virtual camera (p = (u, v, 1),
// H = K_grid R K_ref^-1, e = K_grid t of relativePose), so d pixel / d q = (e_xy h_z - h_xy e_z) / h_z^2.
// Infinite where h_z <= 0 (not in front of the virtual camera).
DisplacementRate pinholeDisplacementRate(const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid);

// The pinhole camera's ReferenceShift (DepthMesh.h): with h as above, the virtual pixel x(u, v, q) moves
// by J = d x / d(u, v) per reference pixel and by d x / d q per unit of q, so the virtual pixel x(u, v, q)
// meets a surface drawn at q + dq at the reference position (u, v) - J^-1 (d x / d q) dq: (du, dv) =
// J^-1 (d x / d q). False where h_z <= 0 or J is singular.
ReferenceShift pinholeReferenceShift(const Camera& reference, const Camera& virtualCamera, const RenderGrid& grid);

// Where OpenGL's viewport transform puts `vertex` under `clip` (with the viewport 0, 0, W, H), in grid
// pixel positions (fragment centres at integers), and its q; evaluated in double. False when the
// point is not in front of the camera (w_clip <= 0).
bool clipToPixel(const Mat4& clip, const RenderGrid& grid, const double vertex[4], double& x, double& y, double& q);

}  // namespace vs
