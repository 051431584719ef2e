#include "Mesh/MeshSynthesizer.h"

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "Common/Error.h"
#include "Mesh/MeshPly.h"
#include "Plan/MissingDepth.h"
#include "Synth/Colour.h"
#include "Pipeline/FrameLoop.h"
#include "Synth/Parallel.h"

namespace vs {

namespace {

template <typename T>
void release(std::vector<T>& buffer) {
  std::vector<T>().swap(buffer);
}

// Frees a drawn mesh's arrays (releaseBuffersAfterEachStep); its sizes and counts stay.
void releaseMeshArrays(DepthMesh& mesh) {
  release(mesh.gridU);
  release(mesh.gridV);
  release(mesh.vertices);
  release(mesh.boundary);
  release(mesh.cellSplit);
  release(mesh.valid);
  release(mesh.triangles);
  release(mesh.points);
  release(mesh.farthestOrphans);
}

void releaseLayer(WarpedLayer& layer) {
  release(layer.inverseDepth);
  for (std::vector<float>& colour : layer.colour) release(colour);
  release(layer.edge);
}

class MeshFrameRenderer : public FrameRenderer {
public:
  MeshFrameRenderer(const Scene& scene, const Plan& plan, const MeshSettings& settings)
      : scene_(scene), synthesizer_(scene_, plan, settings) {
    if (scene_.settings.frameCount <= 1) synthesizer_.releaseBuffersAfterEachStep();
  }
  void render(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times) override {
    synthesizer_.synthesize(references, output, times);
  }
  // The context's thread loads Mesa and LLVM: the pool's workers are started first (Parallel.h).
  void firstInputsRead() override {
    startWorkerThreads();
    synthesizer_.startRenderer();
  }
  std::vector<std::string> prepare(const std::vector<ReferenceFrame>& firstFrame) override {
    std::vector<std::string> lines = synthesizer_.decideMissingDepth(firstFrame);
    // The first frame's meshes are built here (and used for it) so that their size is in the plan.
    synthesizer_.buildMeshes(firstFrame);
    // The context was created meanwhile on its own thread: the renderer is named (or its error thrown,
    // the outputs still temporaries) once it is there.
    lines.push_back("renderer: OpenGL: " + synthesizer_.rendererDescription());
    lines.push_back(synthesizer_.meshSizeLine());
    return lines;
  }
  std::vector<std::string> plan() const override { return synthesizer_.plan(); }
  std::vector<std::pair<std::string, std::string>> decisions() const override {
    std::vector<std::pair<std::string, std::string>> fields = synthesizer_.decisions().fields();
    for (const auto& field : synthesizer_.meshSizeFields()) fields.push_back(field);
    return fields;
  }
  int64_t uncoveredSamples() const override { return int64_t(synthesizer_.holesAfterBlend()); }
  std::vector<NamedOutput> extraOutputs() const override { return synthesizer_.plyOutputs(); }
  void commitOutputs() override { synthesizer_.commitPlyFiles(); }
  // A pose trace (VirtualPoseTraceName): the plan is made again for the moved camera, as ViewSyn does.
  bool moveVirtualCamera(const Camera& camera) override {
    scene_.virtualCamera = camera;  // the synthesizer reads the scene it was given: this copy
    synthesizer_.virtualCameraMoved(makePlan(scene_, Tool::MeshRender));
    return true;
  }

private:
  Scene scene_;  // a copy: a pose trace moves its virtual camera
  MeshSynthesizer synthesizer_;
};

}  // namespace

MeshSettings readMeshSettings(const Config& config) {
  MeshSettings settings;
  settings.discontinuityThreshold = config.getDouble("MeshDiscontinuityThreshold");
  settings.gridStep = std::stoi(config.getString("MeshGridStep"));
  settings.maxError = config.getDouble("MeshMaxError");
  settings.maxColourError = config.getDouble("MeshMaxColourError");
  settings.plyPath = config.getPath("MeshPlyOutput");
  return settings;
}

MeshSynthesizer::MeshSynthesizer(const Scene& scene, const Plan& plan, const MeshSettings& settings)
    : scene_(scene),
      plan_(plan),
      settings_(settings),
      outputFormat_(scene.settings.textureFormat),
      rgb_(plan.rgb),
      hasChroma_(plan.chroma),
      aligner_(scene.settings, plan.missingDepthLevel) {
  VS_CHECK(plan_.tool == Tool::MeshRender && plan_.blending.weights.size() == scene.settings.references.size());
  lumaGrid_ = lumaGrid(scene.virtualCamera, outputFormat_.width, outputFormat_.height);
  if (hasChroma_ && !rgb_) {
    VS_CHECK(outputFormat_.chroma == ChromaFormat::Yuv420 || outputFormat_.chroma == ChromaFormat::Yuv444);
  }
  buildViews();
}

void MeshSynthesizer::startRenderer() const {
  if (pendingRenderer_.valid() || renderer_ || rendererError_) return;
  const SubPixelSampler sampler(plan_.precision, plan_.filter);
  pendingRenderer_ = std::async(std::launch::async, [sampler] {
    std::unique_ptr<GlMeshRenderer> renderer;
    try {
      renderer = std::make_unique<GlMeshRenderer>();  // the context, current on this thread, and its programs
      renderer->setSampling(&sampler);
      renderer->warmUp();  // llvmpipe's shader variants compiled here, beside the mesh builds; releases the context
    } catch (...) {
      renderer.reset();
      EglContext::releaseCurrentContext();
      throw;
    }
    return renderer;
  });
}

GlMeshRenderer& MeshSynthesizer::renderer() const {
  if (!renderer_) {
    startRenderer();
    if (rendererError_) std::rethrow_exception(rendererError_);  // the error again, for every later call
    try {
      renderer_ = pendingRenderer_.get();
    } catch (...) {
      rendererError_ = std::current_exception();
      throw;
    }
  }
  return *renderer_;
}

std::vector<std::string> MeshSynthesizer::decideMissingDepth(const std::vector<ReferenceFrame>& firstFrame) {
  if (!plan_.missingDepthAuto || plan_.missingDepthDecided) return {};
  vs::decideMissingDepth(scene_, firstFrame, plan_);
  aligner_ = DepthEdgeAligner(scene_.settings, plan_.missingDepthLevel);
  buildViews();  // the meshes drop the missing level's vertices
  return plan_.missingDepthEvidence;
}

void MeshSynthesizer::virtualCameraMoved(const Plan& moved) {
  VS_CHECK(moved.tool == Tool::MeshRender && moved.blending.weights.size() == views_.size());
  const Camera& camera = scene_.virtualCamera;
  if (camera.projection == builtFor_.projection && camera.K == builtFor_.K && camera.R == builtFor_.R &&
      camera.t == builtFor_.t && camera.erp == builtFor_.erp)
    return;  // the same pose: meshes, planes and plan stay
  Plan plan = moved;
  if (plan_.missingDepthDecided) {  // a MissingDepthLevel auto decision of the first frame is kept
    plan.missingDepthLevel = plan_.missingDepthLevel;
    plan.missingDepthFill = plan_.missingDepthFill;
    plan.missingDepthEvidence = plan_.missingDepthEvidence;
    plan.missingDepthDecided = true;
  }
  plan_ = std::move(plan);
  aligner_ = DepthEdgeAligner(scene_.settings, plan_.missingDepthLevel);
  lumaGrid_ = lumaGrid(camera, outputFormat_.width, outputFormat_.height);
  buildViews();              // the adaptive mesh's bound and the depth-buffer planes depend on the camera
  meshesPrebuilt_ = false;   // meshes built for the old camera are built again
}

void MeshSynthesizer::buildViews() {
  builtFor_ = scene_.virtualCamera;
  const SynthesisSettings& s = scene_.settings;
  const MeshSettings& settings = settings_;
  const Scene& scene = scene_;
  views_.clear();
  MeshOptions options;
  options.depthType = s.depthType;
  options.gridStep = settings.gridStep;
  options.discontinuityThreshold = settings.discontinuityThreshold;
  options.missingDepthLevel = plan_.missingDepthLevel;
  options.maxError = settings.maxError;
  options.maxColourError = settings.maxColourError;
  for (const ReferenceView& reference : s.references) {
    // MeshMaxError is in the virtual camera's luma pixels. With an ERP camera the mesh is not merged and
    // the depth-buffer planes come from each frame's projected mesh (Mesh/MeshErp.h).
    const bool erp = projectedPass(reference.camera, scene.virtualCamera);
    ViewState view{DepthMeshBuilder(reference.camera, reference.depthRange, s.depthFormat.width, s.depthFormat.height, options,
                                    erp ? DisplacementRate{} : pinholeDisplacementRate(reference.camera, scene.virtualCamera, lumaGrid_),
                                    erp ? ReferenceShift{} : pinholeReferenceShift(reference.camera, scene.virtualCamera, lumaGrid_)),
                   false, {}, {}, {}, {}, {}, {}};
    InverseDepthRange range;
    view.depthRangeBounded = !erp && sceneInverseDepthRange(reference.camera, reference.depthRange, s.depthType,
                                                            s.depthFormat.width, s.depthFormat.height, scene.virtualCamera, range);
    if (view.depthRangeBounded) view.planes = clipPlanes(range);
    views_.push_back(std::move(view));
  }
}

std::vector<std::string> MeshSynthesizer::plan() const {
  const SynthesisSettings& s = scene_.settings;
  std::vector<std::string> lines;
  lines.push_back("mode: mesh rendering with OpenGL (the renderer is named with the first frame)");
  char line[512];
  std::snprintf(line, sizeof line,
                "mesh: a vertex every %d pixel(s), triangles dropped where camera depths differ by more than %.4g "
                "(1 - z_min / z_max)",
                settings_.gridStep, settings_.discontinuityThreshold);
  lines.push_back(line);
  for (size_t k = 0; k < views_.size(); ++k)
    if (projectedPass(s.references[k].camera, scene_.virtualCamera))
      lines.push_back(s.references[k].label +
                      " view: equirectangular camera(s): the mesh is taken into the virtual camera on the CPU, not merged "
                      "(MeshMaxError and MeshMaxColourError do not apply); depth-buffer planes from each frame's mesh");
    else
      lines.push_back(s.references[k].label + " view: depth-buffer planes " +
                    (views_[k].depthRangeBounded ? "from the scene's depth range" : "from each frame's mesh (the depth range is unbounded in the virtual camera)"));
  for (const std::string& decision : plan_.lines()) lines.push_back(decision);
  if (!settings_.plyPath.empty()) {
    std::string files;
    for (const ReferenceView& reference : s.references)
      files += (files.empty() ? "" : ", ") + plyPathForView(settings_.plyPath, reference.label);
    lines.push_back("PLY of the first frame's meshes: " + files);
  }
  return lines;
}

std::vector<NamedOutput> MeshSynthesizer::plyOutputs() const {
  std::vector<NamedOutput> outputs;
  if (settings_.plyPath.empty()) return outputs;
  for (const ReferenceView& reference : scene_.settings.references)
    outputs.push_back({"MeshPlyOutput (" + reference.label + " view)", plyPathForView(settings_.plyPath, reference.label)});
  return outputs;
}

void MeshSynthesizer::commitPlyFiles() {
  for (auto& file : plyFiles_) file->commit();
}

void MeshSynthesizer::synthesize(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times) {
  VS_CHECK(references.size() == views_.size());
  const SynthesisSettings& s = scene_.settings;
  output.reset(outputFormat_);
  GlMeshRenderer& renderer = this->renderer();  // waits for the context the first time
  if (meshesPrebuilt_) {
    times.depthWarp += prebuildSeconds_;  // built by buildMeshes() for this frame
    meshesPrebuilt_ = false;
  } else {
    const auto start = std::chrono::steady_clock::now();
    buildMeshesNow(references);
    times.depthWarp += secondsSince(start);
  }
  // Every pinhole view's mesh is uploaded first, each into a slot of its own, so that a run of one frame
  // frees all their vertices and lists before the first render: the first view's layers then reuse that
  // memory instead of fresh pages, and the read-back takes over the first view's vertex array (as
  // large: a vertex per sample and a border), whose pages the mesh build has touched.
  std::vector<InverseDepthRange> planes(views_.size());
  {
    const auto start = std::chrono::steady_clock::now();
    for (size_t k = 0; k < views_.size(); ++k) {
      ViewState& view = views_[k];
      const ReferenceView& reference = s.references[k];
      if (projectedPass(reference.camera, scene_.virtualCamera)) continue;
      planes[k] = view.depthRangeBounded ? view.planes
                                         : clipPlanes(meshInverseDepthRange(view.mesh, reference.camera, scene_.virtualCamera));
      renderer.uploadMesh(view.mesh, k);
      // In the driver's buffers now; the colour steps read the mesh's edge flags only.
      if (releaseSpent_ && settings_.plyPath.empty()) {
        renderer.reuseForReadBack(std::move(view.mesh.vertices));
        release(view.mesh.vertices);
        release(view.mesh.triangles);
        release(view.mesh.points);
        release(view.mesh.farthestOrphans);
      }
    }
    times.depthWarp += secondsSince(start);
  }
  for (size_t k = 0; k < views_.size(); ++k) {
    ViewState& view = views_[k];
    const ReferenceView& reference = s.references[k];
    const Frame& texture = *references[k].texture;

    auto start = std::chrono::steady_clock::now();
    const bool projected = projectedPass(reference.camera, scene_.virtualCamera);
    if (projected) {  // ERP: the mesh taken into the virtual camera on the CPU
      if (projectMesh(view.mesh, reference.camera, scene_.virtualCamera, lumaGrid_, projected_))
        renderer.uploadProjectedMesh(projected_);
      else
        renderer.uploadProjectedMesh(ProjectedMesh{{}, {}, {}, {}, {}, &view.mesh});  // nothing in front
      if (releaseSpent_ && settings_.plyPath.empty()) release(view.mesh.vertices);
    } else {
      renderer.useMesh(k);
    }
    times.depthWarp += secondsSince(start);

    start = std::chrono::steady_clock::now();
    // One render per view at luma resolution; U and V come from the same render.
    if (rgb_) {
      yuvToRgb(texture, rgbReference_);
      renderer.uploadTexture({&rgbReference_.planes[0], &rgbReference_.planes[1], &rgbReference_.planes[2]});
    } else {
      renderer.uploadTexture({&texture.planes[0]});
    }
    renderer.setReferenceSphere(meshReferenceSphere(reference.camera));
    if (projected)
      renderer.renderProjected(lumaGrid_, TexelMap{}, view.luma);
    else
      renderer.render(meshClipMatrix(reference.camera, scene_.virtualCamera, lumaGrid_, planes[k]), lumaGrid_, TexelMap{},
                       view.luma);
    if (hasChroma_ && !rgb_) {
      if (outputFormat_.chroma == ChromaFormat::Yuv420)
        renderer.sampleChroma420({&texture.planes[1], &texture.planes[2]}, settings_.discontinuityThreshold, view.chroma);
      else
        renderer.sampleRender({texture.planes[1], texture.planes[2]}, TexelMap{}, view.chroma);
    }
    times.textureWarp += secondsSince(start);

    if (!plyWritten_ && !settings_.plyPath.empty()) {
      plyFiles_.push_back(std::make_unique<SafeOutputFile>(plyPathForView(settings_.plyPath, reference.label),
                                                           s.inputPaths(), "MeshPlyOutput"));
      writeMeshPly(*plyFiles_.back(), view.mesh, reference.camera, texture);
    }
    if (releaseSpent_) {
      releaseMeshArrays(view.mesh);  // drawn and coloured: the next view's layers reuse its memory
      if (k + 1 == views_.size()) renderer.releaseRenderBuffers();
    }
  }
  plyWritten_ = true;

  auto start = std::chrono::steady_clock::now();
  std::vector<const WarpedLayer*> lumaLayers, chromaLayers;
  for (const ViewState& view : views_) {
    lumaLayers.push_back(&view.luma);
    chromaLayers.push_back(&view.chroma);
  }
  blendLayers(lumaLayers, plan_.blending, blendedLuma_);
  if (hasChroma_ && !rgb_) blendLayers(chromaLayers, plan_.blending, blendedChroma_);
  holesAfterBlend_ = blendedLuma_.holeCount();
  if (releaseSpent_)
    for (ViewState& view : views_) {  // blended: hole filling reuses their memory
      releaseLayer(view.luma);
      releaseLayer(view.chroma);
    }
  times.blend += secondsSince(start);

  start = std::chrono::steady_clock::now();
  fillHoles(blendedLuma_, plan_.lumaFill, &lumaFill_);
  if (hasChroma_ && !rgb_) fillHoles(blendedChroma_, plan_.chromaFill, &chromaFill_);
  times.holeFill += secondsSince(start);

  roundLayersToFrame(blendedLuma_, blendedChroma_, rgb_, rgbOutput_, output);
}

void MeshSynthesizer::buildMeshes(const std::vector<ReferenceFrame>& references) {
  const auto start = std::chrono::steady_clock::now();
  buildMeshesNow(references);
  prebuildSeconds_ = secondsSince(start);
  meshesPrebuilt_ = true;
}

void MeshSynthesizer::buildMeshesNow(const std::vector<ReferenceFrame>& references) {
  VS_CHECK(references.size() == views_.size());
  const SynthesisSettings& s = scene_.settings;
  std::vector<const Plane*> lumas;
  for (const ReferenceFrame& reference : references) lumas.push_back(&reference.texture->planes[0]);
  // Each view on a worker thread of its own, from its depth map to its mesh: missing-depth runs
  // filled, edges aligned (each reads only its own state and every view's inputs), mesh built.
  std::vector<size_t> moved(views_.size(), 0);
  parallelRanges(
      int(views_.size()),
      [&](int first, int last) {
        for (size_t k = size_t(first); k < size_t(last); ++k) {
          ViewState& view = views_[k];
          const Plane* depth = references[k].depth;
          if (plan_.missingDepthFill) {
            fillMissingDepthRuns(*depth, plan_.missingDepthLevel, inverseZTable(s.references[k].depthRange), view.filledDepth,
                                 view.filledSamples);
            if (plan_.missingDepthRunTest)
              testFilledRuns(scene_, k, references, plan_.missingDepthLevel, view.filledDepth, view.filledSamples);
            depth = &view.filledDepth;
          }
          view.builder.build(aligner_.align(k, *depth, lumas, moved[k]), view.mesh, lumas[k]);
          if (releaseSpent_) {  // read by the build only
            release(view.filledDepth.samples);
            release(view.filledSamples);
          }
        }
      },
      double(views_.size()));
  alignedDepthSamples_ = 0;
  for (size_t samples : moved) alignedDepthSamples_ += samples;
}

std::string MeshSynthesizer::meshSizeLine() const {
  std::string line = "mesh triangles per view (grid quads before the adaptive merge):";
  for (size_t k = 0; k < views_.size(); ++k) {
    const DepthMesh& mesh = views_[k].mesh;
    char part[256];
    std::snprintf(part, sizeof part, "%s %s %zu (%zu)", k ? "," : "", scene_.settings.references[k].label.c_str(),
                  mesh.triangleCount(), mesh.gridTriangles);
    line += part;
  }
  return line;
}

std::vector<std::pair<std::string, std::string>> MeshSynthesizer::meshSizeFields() const {
  std::vector<std::pair<std::string, std::string>> fields;
  for (size_t k = 0; k < views_.size(); ++k) {
    std::string label = scene_.settings.references[k].label;
    for (char& c : label) c = char(std::tolower(static_cast<unsigned char>(c)));
    fields.push_back({"mesh_triangles_" + label, std::to_string(views_[k].mesh.triangleCount())});
    fields.push_back({"mesh_grid_triangles_" + label, std::to_string(views_[k].mesh.gridTriangles)});
  }
  return fields;
}

int runMeshRender(const Config& config) {
  RunReport report("MeshRender", config);
  runReported(report, [&] {
    const Scene scene = loadScene(config);
    const MeshSettings settings = readMeshSettings(config);
    // The plan refuses what MeshRender cannot do before anything is opened.
    const Plan plan = makePlan(scene, Tool::MeshRender);
    MeshFrameRenderer renderer(scene, plan, settings);
    setWorkerThreads(scene.settings.threads);
    return runSequence("MeshRender", scene, renderer, report);
  });
  return 0;
}

}  // namespace vs
