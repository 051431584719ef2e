#include "Common/Options.h"

namespace vs {

namespace {

OptionSpec intOption(const char* key, long long defaultValue, double lo, double hi, const char* vsrsDefault,
                     const char* help) {
  OptionSpec s;
  s.key = key;
  s.type = OptionType::Int;
  s.defaultValue = std::to_string(defaultValue);
  s.minValue = lo;
  s.maxValue = hi;
  s.vsrsDefault = vsrsDefault;
  s.help = help;
  return s;
}

// The default is text, as the manual and --help print it.
OptionSpec doubleOption(const char* key, const char* defaultValue, double lo, double hi, const char* vsrsDefault,
                        const char* help) {
  OptionSpec s;
  s.key = key;
  s.type = OptionType::Double;
  s.defaultValue = defaultValue;
  s.minValue = lo;
  s.maxValue = hi;
  s.vsrsDefault = vsrsDefault;
  s.help = help;
  return s;
}

OptionSpec autoIntOption(OptionSpec spec, bool autoByDefault = false) {
  spec.allowAuto = true;
  if (autoByDefault) spec.defaultValue = "auto";
  return spec;
}

OptionSpec depthValueOption(const char* key, bool farthest, const char* help, bool required = true) {
  OptionSpec s;
  s.key = key;
  s.type = OptionType::Double;
  s.required = required;
  s.allowInfinity = farthest;
  s.vsrsDefault = "0.0";
  s.help = help;
  return s;
}

OptionSpec textOption(const char* key, OptionType type, bool required, const char* vsrsDefault, const char* help) {
  OptionSpec s;
  s.key = key;
  s.type = type;
  s.required = required;
  s.vsrsDefault = vsrsDefault;
  s.help = help;
  return s;
}

OptionSpec choiceOption(const char* key, std::vector<std::string> choices, const char* defaultValue,
                        const char* vsrsDefault, const char* help) {
  OptionSpec s;
  s.key = key;
  s.type = OptionType::Choice;
  s.choices = std::move(choices);
  s.defaultValue = defaultValue;
  s.vsrsDefault = vsrsDefault;
  s.help = help;
  return s;
}

void addAll(OptionTable& table, const char* section, std::vector<OptionSpec> specs) {
  for (OptionSpec& spec : specs) {
    spec.section = section;
    table.add(std::move(spec));
  }
}

}  // namespace

void addSynthesisOptions(OptionTable& table) {
  constexpr double kMaxSize = 16384;  // per side; larger frames are refused before anything is allocated
  constexpr double kMaxFrames = 1e9;
  addAll(table, "Input sequences",
         {
             intOption("DepthType", 0, 0, 1, "0",
                       "0: depth values are the z coordinate in each camera's own frame; 1: depth values are "
                       "the world z coordinate of the point"),
             intOption("SourceWidth", 1280, 1, kMaxSize, "1280", "Width of every input frame in luma samples (and of the output, unless VirtualWidth is set)"),
             intOption("SourceHeight", 960, 1, kMaxSize, "960", "Height of every input frame in luma samples (and of the output, unless VirtualHeight is set)"),
             intOption("VirtualWidth", 0, 0, kMaxSize, "-",
                       "Width of the virtual view (the output, its ground truth, depth and masks) in luma samples; "
                       "0: SourceWidth. Another size than the inputs' needs the general path (RVS: the virtual "
                       "camera's Resolution)"),
             intOption("VirtualHeight", 0, 0, kMaxSize, "-", "Height of the virtual view in luma samples; 0: SourceHeight"),
             intOption("StartFrame", 0, 0, kMaxFrames, "0", "First frame of the input sequences to synthesize (0-based)"),
             intOption("TotalNumberOfFrames", 300, 1, kMaxFrames, "300",
                       "Number of frames to synthesize from StartFrame on"),
             depthValueOption("LeftNearestDepthValue", false, "Znear of the left depth map: the depth of level 2^bits-1 (from a JSON camera file when absent)", false),
             depthValueOption("LeftFarthestDepthValue", true, "Zfar of the left depth map: the depth of level 0 (inf allowed)", false),
             depthValueOption("RightNearestDepthValue", false, "Znear of the right depth map: the depth of level 2^bits-1", false),
             depthValueOption("RightFarthestDepthValue", true, "Zfar of the right depth map: the depth of level 0 (inf allowed)", false),
         });
  addAll(table, "Cameras",
         {
             textOption("CameraParameterFile", OptionType::Path, true, "cam_param.txt",
                        "Camera parameter file (VSRS format: a name, K, two distortion values, then R and t) holding the three cameras"),
             textOption("LeftCameraName", OptionType::String, false, "param_dog38",
                        "Name of the left reference camera in the camera file (or give the Reference keys)"),
             textOption("VirtualCameraName", OptionType::String, true, "param_dog39", "Name of the virtual camera to synthesize"),
             textOption("RightCameraName", OptionType::String, false, "param_dog41",
                        "Name of the right reference camera; leave every Right key out to extrapolate from the left view alone"),
             intOption("CameraRotationConvention", 0, 0, 1, "-",
                       "0: R in the camera file rotates world to camera (VSRS 4.x); 1: R rotates camera to world "
                       "(VSRS 3.5 data), so it is transposed on reading"),
             textOption("VirtualCameraParameterFile", OptionType::Path, false, "-",
                        "Camera file holding the virtual camera, when it is not CameraParameterFile (RVS's "
                        "VirtualCameraParameterFile)"),
             textOption("InputCameraOverrides", OptionType::String, false, "-",
                        "MPEG-I camera JSON keys replacing those of every reference camera, as a JSON object "
                        "without blanks, e.g. {\"BitDepthDepth\":16} (RVS's InputOverrides)"),
             textOption("VirtualCameraOverrides", OptionType::String, false, "-",
                        "The same for the virtual camera (RVS's VirtualOverrides)"),
             textOption("VirtualPoseTraceName", OptionType::Path, false, "-",
                        "Optional pose trace (CSV: X, Y, Z, Yaw, Pitch, Roll in MPEG-I axes): row StartFrame+n "
                        "moves the virtual camera of frame n, its position added to the camera's, its angles "
                        "replacing the camera's rotation (RVS's VirtualPoseTraceName)"),
         });
  addAll(table, "Files",
         {
             textOption("LeftViewImageName", OptionType::Path, false, "dog038.yuv", "Texture sequence of the left camera (planar YUV)"),
             textOption("RightViewImageName", OptionType::Path, false, "dog041.yuv", "Texture sequence of the right camera (planar YUV)"),
             textOption("LeftDepthMapName", OptionType::Path, false, "depth_dog038.yuv", "Depth sequence of the left camera (YUV; luma is the depth level)"),
             textOption("RightDepthMapName", OptionType::Path, false, "depth_dog041.yuv", "Depth sequence of the right camera (YUV; luma is the depth level)"),
             textOption("OutputVirtualViewImageName", OptionType::Path, true, "dog_virtual039.yuv",
                        "Output sequence of the virtual view; never an input file"),
             textOption("ReferenceVirtualViewImageName", OptionType::Path, false, "-",
                        "Optional ground-truth sequence of the virtual camera: PSNR is reported against it per frame"),
             textOption("QualityMetrics", OptionType::TextList, false, "-",
                        "Metrics against ReferenceVirtualViewImageName besides PSNR, comma-separated: ivpsnr, "
                        "wspsnr, ssim, msssim (doc/metrics.md); per frame and as means in the log, ReportFile and SummaryFile"),
         });
  addAll(table, "Reference views (1 to 32, instead of Left and Right)",
         {
             textOption("ReferenceCameraNames", OptionType::TextList, false, "-",
                        "Reference cameras, comma-separated (v1,v2,v4,v5); replaces every Left and Right key"),
             textOption("ReferenceViewImageNames", OptionType::PathList, false, "-", "Their texture sequences, in the same order"),
             textOption("ReferenceDepthMapNames", OptionType::PathList, false, "-", "Their depth sequences, in the same order"),
             textOption("ReferenceNearestDepthValues", OptionType::TextList, false, "-",
                        "Their Znear values (from a JSON camera file when absent)"),
             textOption("ReferenceFarthestDepthValues", OptionType::TextList, false, "-",
                        "Their Zfar values, inf allowed (from a JSON camera file when absent)"),
             textOption("OutputVirtualDepthMapName", OptionType::Path, false, "-",
                        "Optional output of the virtual view's depth, as levels of the virtual camera's depth range"),
             textOption("OutputVirtualMaskName", OptionType::Path, false, "-",
                        "Optional output: a mask of the virtual view (8-bit YUV, the output's chroma format, chroma "
                        "128): luma 255 where no reference view gave the sample (hole filling made it up), 0 "
                        "elsewhere (RVS's OutputMasks)"),
             textOption("OutputMaskedVirtualDepthMapName", OptionType::Path, false, "-",
                        "Optional output: the virtual view's depth as OutputVirtualDepthMapName writes it, with level 0 "
                        "where the mask is 255 (RVS's MaskedDepthOutputFiles)"),
             depthValueOption("VirtualNearestDepthValue", false, "Znear of the virtual depth output (default: the first reference's)", false),
             depthValueOption("VirtualFarthestDepthValue", true, "Zfar of the virtual depth output (default: the first reference's)", false),
         });
  addAll(table, "Formats",
         {
             intOption("ColorSpace", 0, 0, 1, "0", "0: process in YUV; 1: convert to RGB (BT.601), process, convert back"),
             choiceOption("ChromaFormat", {"420", "400", "444"}, "420", "-", "Chroma format of the texture sequences and the output"),
             intOption("TextureBitDepth", 8, 8, 16, "-",
                       "Bits per texture sample; above 8, samples are little-endian 16-bit words"),
             intOption("DepthBitDepth", 8, 8, 16, "-",
                       "Bits per depth sample; above 8, samples are little-endian 16-bit words"),
             choiceOption("DepthChromaFormat", {"420", "400", "444"}, "420", "-",
                          "Chroma format of the depth files (only their luma is read)"),
         });
  addAll(table, "Synthesis",
         {
             choiceOption("SynthesisMode", {"0", "1", "auto"}, "auto", "0",
                          "0: general 3D warping; 1: 1D parallel (rectified rig); auto: 1D when the rig is rectified"),
             choiceOption("Precision", {"1", "2", "4"}, "2", "2", "Sub-pixel precision of texture look-ups: 1 integer, 2 half, 4 quarter pel"),
             choiceOption("Filter", {"0", "1", "2"}, "1", "1", "Interpolation filter: 0 (bi)linear, 1 (bi)cubic, 2 MPEG-4 AVC 6-tap"),
             intOption("BoundaryNoiseRemoval", 0, 0, 1, "0",
                       "1: remove foreground colour bled onto background along depth edges before blending"),
             intOption("ViewBlending", 0, 0, 1, "0", "0: blend left and right views with baseline weights; 1: take mainly the nearer view"),
             intOption("DepthBlendDifference", 5, 0, 65535, "5",
                       "Two warped depths closer than this (in depth levels) are blended; otherwise the nearer wins"),
             intOption("IvsrsInpaint", 1, 0, 1, "1",
                       "1: fill remaining holes from the background side, then inpaint (iVSRS); 0: plain Telea inpainting of the holes, as VSRS (OpenCV's, reproduced exactly)"),
             autoIntOption(intOption("MissingDepthLevel", -1, -1, 65535, "-",
                       "Depth level meaning 'no depth' (MPEG-I uses 0); such samples are not warped. -1: off, as in VSRS "
                       "(level 0 is Zfar); auto: the plan tests level 0's far reading against the other reference views "
                       "on the first frame and decides, and each filled run is tested in them (doc/missing-depth.md)"),
                           true),
             autoIntOption(intOption("MissingDepthFill", 0, 0, 1, "-",
                       "1: a run of MissingDepthLevel samples along a row between two valid samples takes the "
                       "farther one's level and is warped (marked unreliable); 0: missing samples are not warped; "
                       "auto: with MissingDepthLevel auto, 1 when it finds level 0 missing (runs then tested: the "
                       "nearer side's level or Zfar where the views say so), else 0; with an explicit level, 0"),
                           true),
             intOption("DepthEdgeAlignment", 4, 0, 64, "-",
                       "Samples by which a reference depth edge may move onto its texture edge: the nearer "
                       "surface's depth grows onto its colour (doc/algorithms.md); 0: off, as in VSRS"),
         });
  addAll(table, "1D mode",
         {
             intOption("SplattingOption", 2, 0, 2, "2", "0: no splatting; 1: splat every pixel; 2: splat only near depth boundaries"),
             intOption("BoundaryGrowth", 40, 0, 1000, "40", "Width in pixels by which boundary areas grow (SplattingOption 2)"),
             intOption("MergingOption", 2, 0, 2, "2", "0: z-buffer only; 1: averaging only; 2: adaptive z-buffer and averaging"),
             intOption("DepthThreshold", -1, -1, 255, "75",
                       "Depth difference (8-bit levels) within which the views are mixed (MergingOption 2); -1: "
                       "DepthBlendDifference, as in general mode"),
             intOption("HoleCountThreshold", 30, 0, 49, "30", "Hole count that decides between views (MergingOption 2)"),
             intOption("TemporalImprovementOption", 1, 0, 1, "1", "1: keep static background stable over time"),
             intOption("WarpEnhancementOption", 1, 0, 1, "1", "1: use depth edges to correct warping along boundaries"),
             intOption("CleanNoiseOption", 0, 0, 1, "1", "1: remove isolated noise pixels after merging"),
         });
  addAll(table, "Run",
         {
             intOption("Threads", 0, 0, 256, "-", "Worker threads; 0: all cores"),
             textOption("ReportFile", OptionType::Path, false, "-",
                        "Optional machine-readable report (CSV: one row per frame with PSNR and per-stage seconds)"),
             textOption("SummaryFile", OptionType::Path, false, "-",
                        "Optional JSON summary of the run: tool, effective config, plan, frames, means, exit "
                        "status and error (written also when the run fails; doc/report.md)"),
         });
}

void addMeshOptions(OptionTable& table) {
  addAll(table, "Mesh",
         {
             doubleOption("MeshDiscontinuityThreshold", "0.02", 0.0, 1.0, "-",
                          "A triangle is dropped when 1 - zmin/zmax over its corners exceeds this (a depth "
                          "discontinuity); 1 keeps every triangle"),
             choiceOption("MeshGridStep", {"1", "2", "4", "8"}, "1", "-", "Vertex spacing in pixels: 1 is one vertex per pixel"),
             doubleOption("MeshMaxError", "2", 0.0, 100.0, "-",
                          "Adaptive mesh: planar blocks of grid cells are merged into larger triangles where no "
                          "depth sample moves by more than this many virtual-camera pixels; 0 merges only exact "
                          "planes"),
             doubleOption("MeshMaxColourError", "2.6", 0.0, 65535.0, "-",
                          "Adaptive mesh: where the reference luma changes, a merged block may be off only as far "
                          "as keeps the colour a virtual pixel shows within this many sample values (luma step "
                          "to the neighbour along the epipolar line times the shift in pixels), at most "
                          "MeshMaxError; 0: MeshMaxError alone"),
             textOption("MeshPlyOutput", OptionType::Path, false, "-",
                        "Optional PLY file of the first frame's meshes (vertices with colour)"),
         });
}

OptionTable viewSynOptionTable() {
  OptionTable table("ViewSyn");
  addSynthesisOptions(table);
  return table;
}

OptionTable meshRenderOptionTable() {
  OptionTable table("MeshRender");
  addSynthesisOptions(table);
  addMeshOptions(table);
  return table;
}

}  // namespace vs
