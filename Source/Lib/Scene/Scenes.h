#pragma once
// SceneGen's built-in scenes (doc/scenegen.md, "Scenes"): each has a preset (resolution, frames, rig,
// depth of the backdrop, ...) that keys override, and its primitives built from the settings.
#include <string>
#include <vector>

#include "Scene/Primitives.h"
#include "Scene/SceneGen.h"

namespace vs {

// demo, arc, plane, sphere, tiny.
const std::vector<std::string>& builtInSceneNames();
// One line describing the scene, for --help and the log.
std::string sceneDescription(const std::string& name);

// The scene's own settings (every key's value when unset). An unknown name is a bug: names come from
// the option table's choices.
SceneGenSettings scenePreset(const std::string& name);

// The scene's primitives for these settings (backgroundDepth, sphereRadius, sphereDepth).
std::vector<Primitive> buildScene(const SceneGenSettings& settings);

}  // namespace vs
