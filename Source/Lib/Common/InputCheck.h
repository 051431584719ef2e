#pragma once
// The checks of a scene's files that the run makes before frame 0 and --check makes without running
// (doc/formats-yuv.md, "What is accepted"): inputs by content and size, outputs by name.
#include <string>
#include <vector>

#include "Common/Scene.h"

namespace vs {

// Opens every sequence input of `scene` (each view's texture and depth, the ground-truth view) and
// checks that it is a regular file (a FIFO or device is refused before it is opened), raw YUV or a
// Y4M file matching the configured format (other containers are refused with an ffmpeg command),
// holding a whole number of frames of the configured size (else the message names the key, the
// file, the size found, the frame size and the sizes that would divide the file), and reaching
// StartFrame. Throws InputError listing every problem. Returns warnings, one line each: a depth map
// with more than 1 % of its samples at level 0 while MissingDepthLevel is unset.
std::vector<std::string> checkInputs(const Scene& scene);

// Every file the run writes besides the sequences' outputs (the report), with the key that names
// it: checked by checkOutputs against the inputs and each other.
struct NamedOutput {
  std::string key;
  std::string path;
};

// Checks every output of `scene` (OutputVirtualViewImageName, OutputVirtualDepthMapName, ReportFile,
// SummaryFile)
// plus `extra` (e.g. MeshRender's PLY files): none is an input (the config file and camera file
// included, through any spelling or link), no two are the same file, each folder exists. Creates
// nothing; throws InputError listing every problem.
void checkOutputs(const Scene& scene, const std::vector<NamedOutput>& extra = {});

}  // namespace vs
