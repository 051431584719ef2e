// MeshRender rendering a reference view into its own camera gives that view back, byte for byte (Y, U
// and V), on every Middlebury 2005/2006 scene with the shipped configs (issue 29, item 3): isolated
// level-0 samples, which the orphan rule keeps out of disocclusions, included. The truth is the
// reference picture itself. Skipped when the data folder is absent.
// Level 0 is read as VSRS reads it (MissingDepthLevel -1: every sample has a depth). Under the default
// `auto`, level-0 runs the plan declares missing are filled, and filled samples give way to the other
// reference view by design, so those samples (Flowerpots view 1: 5843 of them) are not the reference's.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Process.h"
#include "TestPaths.h"

namespace vs {
namespace {

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(MeshSelfRender, EveryMiddleburyReferenceReproducesItselfExactly) {
  if (!std::filesystem::exists(test::binDir() / "MeshRender")) GTEST_SKIP() << "Bin/MeshRender is not built";
  std::vector<std::filesystem::path> scenes;
  for (const char* set : {"middlebury2005", "middlebury2006"}) {
    const std::filesystem::path dir = test::dataDir() / set;
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (std::filesystem::exists(entry.path() / "synth_view3_general.cfg")) scenes.push_back(entry.path());
  }
  if (scenes.empty()) GTEST_SKIP() << "no Middlebury 2005/2006 scene under " << test::dataDir();
  EXPECT_EQ(scenes.size(), size_t(19)) << "the data README lists 19 scenes with a view-3 config";
  const std::filesystem::path scratch = test::scratchDir("mesh_self_render");
  const std::string output = (scratch / "self.yuv").string();
  for (const std::filesystem::path& scene : scenes)
    for (const char* view : {"1", "5"}) {  // the configs' left and right reference cameras
      const std::string what = scene.filename().string() + " view " + view;
      const test::ToolResult run = test::runTool(
          "MeshRender",
          std::string("synth_view3_general.cfg VirtualCameraName=param_view") + view +
              " MissingDepthLevel=-1 OutputVirtualViewImageName=" + test::quoted(output),
          scratch, scene);
      ASSERT_EQ(run.exitCode, 0) << what << ": " << run.err;
      const std::string reference = fileBytes(scene / (std::string("view") + view + ".yuv"));
      const std::string rendered = fileBytes(output);
      ASSERT_EQ(rendered.size(), reference.size()) << what;
      size_t differing = 0;
      for (size_t i = 0; i < reference.size(); ++i) differing += reference[i] != rendered[i];
      EXPECT_EQ(differing, size_t(0)) << what << ": samples (Y, U or V) that differ from the reference";
    }
}

}  // namespace
}  // namespace vs
