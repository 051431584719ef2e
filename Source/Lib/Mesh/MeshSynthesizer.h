#pragma once
// MeshRender's per-frame pipeline (doc/meshrender.md):
//   1. mesh from depth: each reference view's depth map becomes a triangle mesh (DepthMesh.h)
//   2. render: each mesh is rendered separately into the virtual camera with OpenGL at luma
//      resolution (GlMeshRenderer.h); the reference position and inverse depth of each sample are
//      read back, the colour is looked up in the view's own frame with ViewSyn's sampler, and 4:2:0
//      U and V come from the same render (each chroma sample from its 2 x 2 luma samples): ViewSyn's
//      WarpedLayers
//   3. blend the views and 4. fill the holes with ViewSyn's blendLayers and fillHoles, with the
//      options the plan decides for the scene (makePlan(scene, Tool::MeshRender): ViewSyn's general
//      path's), 5. round into the output frame
// ColorSpace 1 renders R, G, B at luma resolution instead of Y and U, V, as ViewSyn does.
#include <exception>
#include <future>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "Common/Config.h"
#include "Common/InputCheck.h"
#include "Common/SafeOutput.h"
#include "Common/Scene.h"
#include "Mesh/DepthMesh.h"
#include "Mesh/GlMeshRenderer.h"
#include "Mesh/MeshErp.h"
#include "Mesh/MeshProjection.h"
#include "Plan/Plan.h"
#include "Synth/EdgeAlign.h"
#include "Synth/HoleFill.h"
#include "Synth/Layer.h"
#include "Synth/Synthesizer.h"  // StageTimes, ReferenceFrame

namespace vs {

// MeshRender's own keys (section "Mesh" of meshRenderOptionTable()).
struct MeshSettings {
  double discontinuityThreshold = MeshOptions{}.discontinuityThreshold;  // MeshDiscontinuityThreshold
  int gridStep = 1;                      // MeshGridStep: 1, 2, 4 or 8
  double maxError = MeshOptions{}.maxError;  // MeshMaxError: virtual-camera pixels; adaptive mesh bound
  double maxColourError = MeshOptions{}.maxColourError;  // MeshMaxColourError: sample values; 0 off
  std::string plyPath;                   // MeshPlyOutput; empty: none
};

MeshSettings readMeshSettings(const Config& config);

class MeshSynthesizer {
public:
  // Makes everything that depends on the scene only: mesh grids, camera matrices. The OpenGL context
  // and renderer are created on a thread of their own, started by startRenderer() or else by the first
  // call that needs them (synthesize, rendererDescription), which waits for them and throws InputError
  // when there is no context.
  // `plan`: makePlan(scene, Tool::MeshRender), whose blend and hole-fill options are used as they are.
  MeshSynthesizer(const Scene& scene, const Plan& plan, const MeshSettings& settings);

  // Synthesizes the virtual view of one frame into `output` (reset to the texture format). Mesh
  // building and upload count as depthWarp, rendering and read-back as textureWarp.
  void synthesize(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times);

  // The PLY files MeshPlyOutput names, one per reference view (empty without the key).
  std::vector<NamedOutput> plyOutputs() const;
  // Renames the PLY files written with the first frame into place (the run ended well).
  void commitPlyFiles();
  // MissingDepthLevel auto: the plan's decision on the first frame (Plan/MissingDepth.h); the meshes
  // are rebuilt with it. Returns the decision's lines; none when there is nothing to decide.
  std::vector<std::string> decideMissingDepth(const std::vector<ReferenceFrame>& firstFrame);

  // VirtualPoseTraceName: the scene's virtual camera has moved (the caller changed the Scene this
  // synthesizer reads); `plan` is makePlan for the moved camera. The next frame's meshes are built for
  // it; a MissingDepthLevel auto decision already taken is kept. Nothing changes for the same pose.
  void virtualCameraMoved(const Plan& plan);

  // A run of one frame: each step frees what the later steps do not read (a view's mesh vertices once
  // uploaded, its mesh once drawn and coloured, the render's read-back after the last view, the views'
  // layers once blended), so that the later steps reuse that memory instead of touching fresh pages
  // (as ViewSyn's Synthesizer::releaseBuffersAfterEachStep). mesh(), lumaLayer() and chromaLayer() are
  // then empty after synthesize(); meshSizeLine() and meshSizeFields() belong before it.
  void releaseBuffersAfterEachStep() { releaseSpent_ = true; }

  // Builds the meshes of these references now; the next synthesize() uses them (and counts their time).
  void buildMeshes(const std::vector<ReferenceFrame>& references);
  // The triangles of each view's last mesh, after and before the adaptive merge: a line for the plan,
  // and fields for the JSON summary (mesh_triangles_<label>, mesh_grid_triangles_<label>).
  std::string meshSizeLine() const;
  std::vector<std::pair<std::string, std::string>> meshSizeFields() const;

  // Lines for the plan printed before the first frame: the plan's, and what the renderer adds (the
  // mesh, each view's depth-buffer planes, PLY files). The OpenGL renderer is named by
  // rendererDescription(), known only once the context exists (the first frame's plan lines).
  std::vector<std::string> plan() const;
  const Plan& decisions() const { return plan_; }
  // Waits for the context; throws InputError when none could be created.
  const std::string& rendererDescription() const { return renderer().description(); }
  // Starts creating the context and renderer on a thread of their own (about 45 ms with llvmpipe,
  // its first draw included: GlMeshRenderer::warmUp), to overlap the first frame's mesh build; once.
  void startRenderer() const;
  const BlendOptions& blendOptions() const { return plan_.blending; }
  const HoleFillOptions& holeFillOptions() const { return plan_.lumaFill; }

  // The last frame's intermediate results, for tests and diagnostics.
  const DepthMesh& mesh(size_t view) const { return views_[view].mesh; }
  const WarpedLayer& lumaLayer(size_t view) const { return views_[view].luma; }
  const WarpedLayer& chromaLayer(size_t view) const { return views_[view].chroma; }
  size_t holesAfterBlend() const { return holesAfterBlend_; }
  // Reference depth samples DepthEdgeAlignment moved to the near side in the last frame.
  size_t alignedDepthSamples() const { return alignedDepthSamples_; }

private:
  // The renderer, once its thread has created it (waits for it the first time; rethrows its error).
  GlMeshRenderer& renderer() const;
  void buildViews();
  void buildMeshesNow(const std::vector<ReferenceFrame>& references);  // depth maps prepared, meshes built  // the per-view mesh builders and depth-buffer planes, from plan_

  struct ViewState {
    DepthMeshBuilder builder;
    bool depthRangeBounded = false;  // the scene's depth range bounds q in the virtual camera
    InverseDepthRange planes;        // depth-buffer planes when bounded
    DepthMesh mesh;
    WarpedLayer luma;                // Y, or R, G, B with ColorSpace 1
    WarpedLayer chroma;              // U, V at chroma resolution
    Plane filledDepth;               // MissingDepthFill: the depth map with missing runs filled
    std::vector<uint8_t> filledSamples;
  };

  const Scene& scene_;
  Plan plan_;  // changed only by decideMissingDepth
  MeshSettings settings_;
  FrameFormat outputFormat_;
  bool rgb_;        // plan_.rgb
  bool hasChroma_;  // plan_.chroma
  // Created on its own thread (EGL binds a context to one thread at a time: that thread releases it,
  // and each GlMeshRenderer call makes it current on the calling thread); renderer() takes it over.
  mutable std::future<std::unique_ptr<GlMeshRenderer>> pendingRenderer_;
  mutable std::unique_ptr<GlMeshRenderer> renderer_;
  mutable std::exception_ptr rendererError_;  // what creating it threw
  RenderGrid lumaGrid_;
  ProjectedMesh projected_;  // ERP cameras: a view's mesh in clip coordinates (Mesh/MeshErp.h)
  Camera builtFor_;  // the virtual camera views_ were built for
  DepthEdgeAligner aligner_;  // DepthEdgeAlignment, as ViewSyn does it
  std::vector<ViewState> views_;
  BlendedLayer blendedLuma_, blendedChroma_;
  HoleFillScratch lumaFill_, chromaFill_;  // reused every frame
  Frame rgbReference_, rgbOutput_;
  size_t holesAfterBlend_ = 0;
  size_t alignedDepthSamples_ = 0;
  bool plyWritten_ = false;
  bool meshesPrebuilt_ = false;  // buildMeshes() ran for the next frame
  bool releaseSpent_ = false;    // releaseBuffersAfterEachStep()
  double prebuildSeconds_ = 0.0;
  std::vector<std::unique_ptr<SafeOutputFile>> plyFiles_;  // temporary until commitPlyFiles()
};

// MeshRender's run(): loads the scene, creates the renderer and runs the sequence (runSequence).
// Returns the exit code.
int runMeshRender(const Config& config);

}  // namespace vs
