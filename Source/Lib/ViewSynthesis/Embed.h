#pragma once
// The embeddable API: ViewSyn's synthesis on cameras and frames held in memory; no file is read or
// written. For a program that synthesizes views inside its own loop, such as an encoder's
// view-synthesis optimisation (3D-HEVC's renderer model in HTM). After `cmake --install`:
//   find_package(ViewSynthesis REQUIRED)
//   target_link_libraries(app PRIVATE ViewSynthesis::Synth)
// and `#include <ViewSynthesis/Embed.h>`. The output is the same, bit for bit, as ViewSyn's for the
// same cameras, frames and keys (Test/Consumer checks it).
#include <memory>
#include <string>
#include <vector>

#include "Common/Camera.h"
#include "Common/Frame.h"

namespace vs {

struct EmbeddedView {
  Camera camera;       // K, R (world to camera) and t (the centre), as a VSRS 4.x camera file gives them
  double znear = 0.0;  // the depth of the largest level (DepthType's meaning: camera or world z)
  double zfar = 0.0;   // the depth of level 0; may be infinite (DepthType 0)
};

struct EmbeddedScene {
  FrameFormat texture;                   // of every reference texture and of the output
  int depthBitDepth = 8;                 // levels of the depth planes: 0 .. 2^depthBitDepth - 1
  std::vector<EmbeddedView> references;  // 1 to 32 views (kMaxReferenceViews)
  Camera virtualCamera;
  // Any other ViewSyn key as "Key=Value" (DepthType=1, Precision=4, Threads=1, ...; doc/manual.md),
  // checked as on ViewSyn's command line. Keys that name files are refused: nothing is read or written.
  std::vector<std::string> settings;
};

class ViewSynthesizer {
public:
  // Checks the scene and decides the plan as ViewSyn does; throws InputError listing every problem.
  explicit ViewSynthesizer(const EmbeddedScene& scene);
  ~ViewSynthesizer();
  ViewSynthesizer(const ViewSynthesizer&) = delete;
  ViewSynthesizer& operator=(const ViewSynthesizer&) = delete;

  // One frame: references[k] is view k's texture (the scene's texture format) and its depth levels (a
  // plane of the texture's size; only luma of a depth file). `output` is reset to the texture format.
  // Frames of a sequence go in order (the 1D path's temporal fill keeps the previous frame).
  void synthesize(const std::vector<ReferenceFrame>& references, Frame& output);

  // The plan in words, as ViewSyn prints it at the start.
  std::vector<std::string> plan() const;

private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace vs
