#include "Common/InputCheck.h"

#include <cstdio>

#include "Common/Config.h"
#include "Common/Error.h"
#include "Common/SafeOutput.h"
#include "Common/Yuv.h"

namespace vs {

namespace {

std::string plural(uint64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// One sequence input: the key that names it, what it is for the message, and its format keys.
struct SequenceInput {
  std::string key;   // "LeftViewImageName", "ReferenceDepthMapNames item 3"
  std::string what;  // "texture of the Left view"
  std::string path;
  FrameFormat format;
  const char* chromaKey;
  const char* bitDepthKey;
  bool depth = false;
};

std::vector<SequenceInput> sequenceInputs(const SynthesisSettings& s) {
  std::vector<SequenceInput> inputs;
  for (size_t k = 0; k < s.references.size(); ++k) {
    const ReferenceView& view = s.references[k];
    const bool leftRight = view.label == "Left" || view.label == "Right";
    const std::string item = " item " + std::to_string(k + 1);
    inputs.push_back({leftRight ? view.label + "ViewImageName" : "ReferenceViewImageNames" + item,
                      "texture of the " + view.label + " view", view.texturePath, s.textureFormat, "ChromaFormat",
                      "TextureBitDepth", false});
    inputs.push_back({leftRight ? view.label + "DepthMapName" : "ReferenceDepthMapNames" + item,
                      "depth of the " + view.label + " view", view.depthPath, view.depthFormat, "DepthChromaFormat",
                      "DepthBitDepth", true});
  }
  if (!s.referenceViewPath.empty())
    inputs.push_back({"ReferenceVirtualViewImageName", "ground truth of the virtual view", s.referenceViewPath,
                      s.virtualFormat(), "ChromaFormat", "TextureBitDepth", false});
  return inputs;
}

}  // namespace

std::vector<std::string> checkInputs(const Scene& scene) {
  const SynthesisSettings& s = scene.settings;
  ProblemList problems;
  std::vector<std::string> warnings;
  for (const SequenceInput& input : sequenceInputs(s)) {
    const std::string role = input.key + " (" + input.what + ")";
    try {
      YuvReader reader(input.path, input.format);
      const uint64_t frameBytes = input.format.frameBytes();
      if (reader.trailingBytes() != 0) {
        std::string message = role + ": " + input.path + ": " + std::to_string(reader.fileBytes()) +
                              " bytes is not a whole number of " + describeFormat(input.format) + " frames (" +
                              std::to_string(frameBytes) + " bytes a frame" + (reader.y4m() ? " after its FRAME line" : "") +
                              "): " + plural(uint64_t(reader.frameCount()), "whole frame", "whole frames") + " and " +
                              std::to_string(reader.trailingBytes()) + " bytes over";
        if (!reader.y4m()) {
          const std::string sizes = wholeFrameSizes(reader.fileBytes(), input.format);
          message += sizes.empty() ? "; no nearby size divides the file" : "; sizes that divide the file: " + sizes;
          const bool virtualSize = input.key == "ReferenceVirtualViewImageName" && s.virtualResized();
          message += std::string("; check ") + (virtualSize ? "VirtualWidth, VirtualHeight, " : "SourceWidth, SourceHeight, ") +
                     input.chromaKey + " and " + input.bitDepthKey;
          if (reader.frameCount() > 0)
            message += " (to use the first frames of a file with extra bytes at its end, copy them: head -c " +
                       std::to_string(uint64_t(reader.frameCount()) * frameBytes) + " FILE > FIRST.yuv)";
        } else {
          message += " (a cut Y4M file?)";
        }
        problems.add(message);
        continue;
      }
      if (s.startFrame >= reader.frameCount()) {
        problems.add(role + ": " + input.path + ": StartFrame " + std::to_string(s.startFrame) +
                     " is beyond the end of the file (" + std::to_string(reader.frameCount()) + " whole frames of " +
                     std::to_string(frameBytes) + " bytes)");
        continue;
      }
      if (input.depth && s.missingDepthLevel < 0 && !s.missingDepthAuto) {
        // Level 0 as "no depth" (Middlebury, open3d) read as the farthest plane gives wrong geometry
        // (an explicit MissingDepthLevel -1; auto tests it).
        Plane luma;
        reader.readLuma(s.startFrame, luma);
        size_t zeros = 0;
        for (uint16_t level : luma.samples) zeros += level == 0;
        const double share = luma.samples.empty() ? 0.0 : double(zeros) / double(luma.samples.size());
        if (share > 0.01) {
          char line[512];
          std::snprintf(line, sizeof line,
                        "%s: %.1f %% of the depth samples of frame %lld are at level 0; if level 0 means unknown "
                        "depth (as in the Middlebury and open3d sets), set MissingDepthLevel 0 (and MissingDepthFill 1)",
                        input.path.c_str(), 100.0 * share, (long long)s.startFrame);
          warnings.push_back(line);
        }
      }
    } catch (const InputError& e) {
      problems.add(role + ": " + e.what());
    }
  }
  problems.throwIfAny((s.configFile.empty() ? std::string("configuration") : s.configFile) + ": input files:");
  return warnings;
}

void checkOutputs(const Scene& scene, const std::vector<NamedOutput>& extra) {
  const SynthesisSettings& s = scene.settings;
  std::vector<NamedOutput> outputs;
  if (!s.outputPath.empty()) outputs.push_back({"OutputVirtualViewImageName", s.outputPath});
  if (!s.virtualDepthPath.empty()) outputs.push_back({"OutputVirtualDepthMapName", s.virtualDepthPath});
  if (!s.virtualMaskPath.empty()) outputs.push_back({"OutputVirtualMaskName", s.virtualMaskPath});
  if (!s.maskedVirtualDepthPath.empty())
    outputs.push_back({"OutputMaskedVirtualDepthMapName", s.maskedVirtualDepthPath});
  if (!s.reportPath.empty()) outputs.push_back({"ReportFile", s.reportPath});
  if (!s.summaryPath.empty()) outputs.push_back({"SummaryFile", s.summaryPath});
  outputs.insert(outputs.end(), extra.begin(), extra.end());
  const std::vector<std::string> inputs = s.inputPaths();
  ProblemList problems;
  for (size_t i = 0; i < outputs.size(); ++i) {
    try {
      SafeOutputFile::checkPath(outputs[i].path, inputs, outputs[i].key);
    } catch (const InputError& e) {
      problems.add(e.what());
    }
    for (size_t j = 0; j < i; ++j)
      if (sameFile(outputs[i].path, outputs[j].path))
        problems.add(outputs[i].key + " '" + outputs[i].path + "' is the same file as " + outputs[j].key + " '" +
                     outputs[j].path + "'; give each output a file of its own");
  }
  problems.throwIfAny((s.configFile.empty() ? std::string("configuration") : s.configFile) + ": output files:");
}

}  // namespace vs
