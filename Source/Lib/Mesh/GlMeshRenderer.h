#pragma once
// Renders a reference view's mesh into a pixel grid of the virtual camera with OpenGL 3.3 core, headless
// (doc/meshrender.md, "Rendering"). Read back per sample: the reference pixel position the sample
// shows and the inverse virtual depth q = 1 / z; then, on the CPU, the reference's colour there
// (setSampling) and whether the sample lies next to a depth edge of the reference.
//
// Render target: one RGBA32F colour attachment (reference position, q, flags) and a
// GL_DEPTH_COMPONENT32F depth buffer, in one framebuffer object sized for the largest grid so far. The
// colour is looked up on the CPU from the read-back reference positions with ViewSyn's sampler, so each
// sample is coloured once (not once per overlapping fragment) and 4:2:0 chroma comes from the same
// render (sampleChroma420). Buffers and the framebuffer are kept across frames.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "Common/Frame.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/EglContext.h"
#include "Mesh/MeshErp.h"
#include "Mesh/MeshProjection.h"
#include "Synth/Interpolation.h"
#include "Synth/Layer.h"

namespace vs {

// How a reference pixel position (u, v) maps to a texel position of the uploaded planes: scale * (u, v)
// + offset. Luma: (1, 0). 4:2:0 chroma, whose sample i sits at luma 2 i + 0.5: (1/2, -1/4).
struct TexelMap {
  double scale = 1.0;
  double offset = 0.0;
};

// Per-sample extras of a render, for tests and diagnostics.
struct RenderExtras {
  std::vector<float> referenceU, referenceV;  // reference pixel position shown; NaN where nothing was drawn
};

class GlMeshRenderer {
public:
  // Creates the EGL context and the GL objects. Throws InputError when no context can be created.
  GlMeshRenderer();
  ~GlMeshRenderer();
  GlMeshRenderer(const GlMeshRenderer&) = delete;
  GlMeshRenderer& operator=(const GlMeshRenderer&) = delete;

  // Vendor, renderer and version of the OpenGL context, and the EGL platform it came from.
  const std::string& description() const;

  // How colour is looked up in the reference texture: ViewSyn's sub-pixel sampling (Precision and
  // Filter: the position rounded to the 1/precision grid, then the sampler's separable kernel, with the
  // sampler's own kernel weights), or, with nullptr (the default), bilinear at the exact position.
  void setSampling(const SubPixelSampler* sampler);

  // Uploads the mesh's vertices and triangles into `slot` (kept until the next upload there; each slot
  // has buffers of its own, so the meshes of several views can be uploaded before the first is drawn
  // and their arrays freed) and makes it the one the next renders draw. The renders read the mesh's
  // edge flags (DepthMesh::edgeAt): it must outlive them; its vertices and lists are not read again.
  void uploadMesh(const DepthMesh& mesh, size_t slot = 0);
  // Draws a small mesh the way render() draws, into a small framebuffer, and reads it back; leaves the
  // renders as they were (slot 0 holds nothing drawable until uploadMesh). A software rasteriser
  // (llvmpipe) compiles its shader variants for a state at the first draw in it: a caller that creates
  // the renderer on a thread of its own calls this there, so that the compiling overlaps other work
  // instead of lengthening the first render (about 13 ms of llvmpipe's LLVM on Art). Releases the
  // context from the calling thread.
  void warmUp();
  // Makes the mesh uploaded into `slot` the one the next renders draw.
  void useMesh(size_t slot);
  // Keeps pointers to 1 to 3 planes of one size: the texture the next renders are coloured with
  // (looked up on the CPU, where each render's fragments say). The planes must outlive those renders
  // and the sampleChroma420 after them (no copy is made).
  void uploadTexture(const std::vector<const Plane*>& planes);
  // Renders the uploaded mesh, textured with the uploaded planes, into `grid` through `clip`
  // (meshClipMatrix). `layer` is reset to the grid's size with as many channels as planes were
  // uploaded: colour, q (kNoDepth where nothing was drawn) and edge (1 where the sample's triangle has
  // a vertex on a dropped triangle). Throws InputError when the grid exceeds the GL limits.
  void render(const Mat4& clip, const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer,
              RenderExtras* extras = nullptr);
  // ERP cameras (Mesh/MeshErp.h): uploads a mesh already in the virtual camera's clip coordinates (kept
  // until the next call; its DepthMesh must outlive the renders), and renders it as render() does,
  // into `grid`, read back and coloured the same way.
  void uploadProjectedMesh(const ProjectedMesh& mesh);
  void renderProjected(const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer,
                       RenderExtras* extras = nullptr);
  // How the uploaded reference's planes continue beyond their edges (Synth/Interpolation.h's
  // SphereEdges; meshReferenceSphere for a camera): a full-circle ERP reference is read round its wrap
  // and, where it reaches a pole, across it, by every colour look-up within four samples of its edges
  // (luma and chroma alike, as ViewSyn's warps), and sampleChroma420 combines the reference positions
  // of neighbouring samples across its seam (its first plane's width a whole turn). The default, none:
  // the edge samples repeat.
  void setReferenceSphere(const SphereEdges& edges);
  // The last render's samples coloured from other planes (4:4:4 chroma at luma resolution, texel map
  // as given): `layer` gets the render's q and edges and the planes' colours.
  void sampleRender(const std::vector<Plane>& planes, const TexelMap& texelMap, WarpedLayer& layer) const;
  // 4:2:0 chroma from the last render at luma resolution, without a render of its own: chroma sample
  // (i, j) at luma (2i + 0.5, 2j + 0.5) shows the front surface of its 2 x 2 luma samples (the nearest
  // one and those within `sameSurface`, 1 - q / q_front); its reference position is the four's mean
  // when all four are on that surface, else the front sample's, moved half a luma pixel along the
  // reference positions of its neighbours on that surface. U and V are sampled there.
  void sampleChroma420(const std::vector<const Plane*>& planes, double sameSurface, WarpedLayer& layer) const;
  // Frees what the last render left on this side (its read-back samples, their edge flags) and forgets
  // the texture's planes and the uploaded mesh, for a run that renders nothing more: its later steps reuse the
  // memory instead of touching fresh pages. The next render needs uploadMesh and uploadTexture again.
  void releaseRenderBuffers();
  // Gives the read-back `storage`'s memory when it holds more than the read-back has (its values do not
  // matter: every render overwrites what it reads back), and frees `storage` either way. A run of one
  // frame hands over an uploaded mesh's vertex array, whose pages are touched already.
  void reuseForReadBack(std::vector<float>&& storage);

private:
  // Reads the drawn framebuffer back and colours it into `layer` (both passes).
  void finishRender(const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer, RenderExtras* extras);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs
