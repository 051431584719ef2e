#include "ViewSynthesis/Embed.h"

#include <cmath>
#include <cstdio>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/Options.h"
#include "Common/Scene.h"
#include "Plan/Plan.h"
#include "Synth/Parallel.h"
#include "Synth/Synthesizer.h"

namespace vs {

namespace {

// A double as config text that reads back to the same bits ("inf" for infinity).
std::string exactText(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ",") + item;
  return text;
}

// The scene's keys as ViewSyn's overrides: what the embedder gave, then the formats and the views
// (two views under the Left and Right keys, as a VSRS config names them; other counts as lists).
// The file keys that ViewSyn requires name nothing that is opened (distinct names: an output equal to
// an input is refused).
std::vector<std::string> sceneKeys(const EmbeddedScene& scene, const OptionTable& table, ProblemList& problems) {
  std::vector<std::string> keys;
  for (const std::string& setting : scene.settings) {
    const OptionSpec* spec = table.find(setting.substr(0, setting.find('=')));
    if (spec && (spec->type == OptionType::Path || spec->type == OptionType::PathList))
      problems.add("embedded scene: '" + setting + "' names a file; the embedded API reads and writes none");
    else
      keys.push_back(setting);
  }
  const FrameFormat& f = scene.texture;
  keys.insert(keys.end(), {"SourceWidth=" + std::to_string(f.width), "SourceHeight=" + std::to_string(f.height),
                           "TextureBitDepth=" + std::to_string(f.bitDepth),
                           std::string("ChromaFormat=") + chromaFormatName(f.chroma),
                           "DepthBitDepth=" + std::to_string(scene.depthBitDepth), "DepthChromaFormat=400",
                           "TotalNumberOfFrames=1", "CameraParameterFile=(memory)",
                           "VirtualCameraName=" + scene.virtualCamera.name, "OutputVirtualViewImageName=(memory output)"});
  const size_t n = scene.references.size();
  if (n == 2) {
    const char* sides[2] = {"Left", "Right"};
    for (size_t k = 0; k < 2; ++k) {
      const EmbeddedView& view = scene.references[k];
      const std::string side = sides[k];
      keys.insert(keys.end(), {side + "CameraName=" + view.camera.name, side + "ViewImageName=(memory texture " + side + ")",
                               side + "DepthMapName=(memory depth " + side + ")", side + "NearestDepthValue=" + exactText(view.znear),
                               side + "FarthestDepthValue=" + exactText(view.zfar)});
    }
  } else {
    std::vector<std::string> names, textures, depths, nears, fars;
    for (const EmbeddedView& view : scene.references) {
      names.push_back(view.camera.name);
      textures.push_back("(memory texture " + std::to_string(textures.size()) + ")");
      depths.push_back("(memory depth " + std::to_string(depths.size()) + ")");
      nears.push_back(exactText(view.znear));
      fars.push_back(exactText(view.zfar));
    }
    keys.insert(keys.end(), {"ReferenceCameraNames=" + joined(names), "ReferenceViewImageNames=" + joined(textures),
                             "ReferenceDepthMapNames=" + joined(depths), "ReferenceNearestDepthValues=" + joined(nears),
                             "ReferenceFarthestDepthValues=" + joined(fars)});
  }
  return keys;
}

}  // namespace

struct ViewSynthesizer::State {
  Scene scene;
  Plan plan;
  std::unique_ptr<Synthesizer> synthesizer;  // holds a reference to `scene`
};

ViewSynthesizer::ViewSynthesizer(const EmbeddedScene& embedded) : state_(std::make_unique<State>()) {
  const OptionTable table = viewSynOptionTable();
  ProblemList problems;
  if (embedded.references.empty() || embedded.references.size() > kMaxReferenceViews)
    problems.add("embedded scene: " + std::to_string(embedded.references.size()) + " reference views; expected 1 to " +
                 std::to_string(kMaxReferenceViews));
  const std::vector<std::string> keys = sceneKeys(embedded, table, problems);
  problems.throwIfAny("embedded scene:");
  const Config config = Config::fromText(table, "", "embedded scene", ".", keys);
  Scene& scene = state_->scene;
  scene.settings = readSynthesisSettings(config);
  SynthesisSettings& s = scene.settings;
  for (size_t k = 0; k < s.references.size(); ++k) s.references[k].camera = embedded.references[k].camera;
  scene.virtualCamera = embedded.virtualCamera;
  if (!s.virtualDepthRangeSet) {
    s.virtualDepthRange = s.references[0].depthRange;
    s.virtualDepthRange.bitDepth = s.depthFormat.bitDepth;
  }
  state_->plan = makePlan(scene);
  setWorkerThreads(s.threads);
  if (state_->plan.copyOf < 0) state_->synthesizer = std::make_unique<Synthesizer>(scene, state_->plan);
}

ViewSynthesizer::~ViewSynthesizer() = default;

void ViewSynthesizer::synthesize(const std::vector<ReferenceFrame>& references, Frame& output) {
  const SynthesisSettings& s = state_->scene.settings;
  if (references.size() != s.references.size())
    throw InputError("ViewSynthesizer::synthesize: " + std::to_string(references.size()) + " reference frames for " +
                     std::to_string(s.references.size()) + " views");
  for (size_t k = 0; k < references.size(); ++k) {
    const ReferenceFrame& frame = references[k];
    if (!frame.texture || !frame.depth || frame.texture->format != s.textureFormat ||
        frame.depth->width != s.textureFormat.width || frame.depth->height != s.textureFormat.height)
      throw InputError("ViewSynthesizer::synthesize: reference " + std::to_string(k) +
                       ": expected a texture of the scene's format and a depth plane of its size");
  }
  if (state_->plan.copyOf >= 0) {
    output = *references[size_t(state_->plan.copyOf)].texture;
    return;
  }
  StageTimes times;
  state_->synthesizer->synthesize(references, output, times);
}

std::vector<std::string> ViewSynthesizer::plan() const { return state_->plan.lines(); }

}  // namespace vs
