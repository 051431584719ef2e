#pragma once
// Scene files (cfg/scenes/*.scene): a SceneGen scene written out as text, its preset settings and its
// objects, so that a scene can be changed or added without touching code. The built-in names (demo,
// arc, ...) stay as shortcuts; cfg/scenes/ holds each of them as a file that renders byte-identically
// (Test/Unit/SceneFileTest.cpp). The syntax is in doc/scenegen.md, "Scene files".
#include <string>
#include <vector>

#include "Scene/Primitives.h"
#include "Scene/SceneGen.h"

namespace vs {

struct SceneFile {
  SceneGenSettings preset;         // the in-class defaults overridden by the file's settings lines
  std::string description;         // the file's Description line (empty when absent)
  std::vector<Primitive> objects;  // in file order
};

// Parses scene text read from `name` (for messages). The scene's name (`preset.scene`) is the file
// name without folder and extension. Throws InputError listing every problem with `name:line`.
SceneFile parseSceneFile(const std::string& text, const std::string& name);

// Reads and parses the file at `path`.
SceneFile readSceneFile(const std::string& path);

}  // namespace vs
