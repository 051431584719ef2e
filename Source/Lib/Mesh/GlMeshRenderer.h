#pragma once
// Renders a reference view's mesh into a pixel grid of the virtual camera with OpenGL 3.3 core, headless
// (doc/meshrender.md, "Rendering"). Read back per sample: the reference's colour, interpolated in float
// from the reference planes uploaded as float textures (setSampling); the inverse virtual depth q = 1 / z; the
// reference pixel position the sample shows; and whether its triangle touches a dropped one (a depth
// edge of the reference).
//
// Render targets: two RGBA32F colour attachments (colour and q; reference position and flags) and a
// GL_DEPTH_COMPONENT32F depth buffer, in one framebuffer object sized for the largest grid so far.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "Common/Frame.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/EglContext.h"
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

  // Uploads the mesh's vertices and triangles (kept until the next call).
  void uploadMesh(const DepthMesh& mesh);
  // Uploads 1 to 3 planes of one size as one float texture (kept until the next call).
  void uploadTexture(const std::vector<const Plane*>& planes);
  // Renders the uploaded mesh, textured with the uploaded planes, into `grid` through `clip`
  // (meshClipMatrix). `layer` is reset to the grid's size with as many channels as planes were
  // uploaded: colour, q (kNoDepth where nothing was drawn) and edge (1 where the sample's triangle has
  // a vertex on a dropped triangle). Throws InputError when the grid exceeds the GL limits.
  void render(const Mat4& clip, const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer,
              RenderExtras* extras = nullptr);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs
