// Synthesizes a view through the embeddable API (ViewSynthesis/Embed.h) on frames it holds in memory:
// the files are read and written here, by the consumer, never by the synthesizer.
//   EmbedConsumer CAMERAS.txt WIDTH HEIGHT FRAMES VIRTUAL OUT.yuv  NAME ZNEAR ZFAR TEXTURE.yuv DEPTH.yuv ...
//                 [Key=Value ...]
// (one NAME ZNEAR ZFAR TEXTURE DEPTH group per reference view; 8-bit 4:2:0 texture and depth files;
// Key=Value: other ViewSyn keys, given to the synthesizer as they are)
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include <ViewSynthesis/Embed.h>

#include "Common/CameraFile.h"
#include "Common/Yuv.h"

int main(int argCount, char** arguments) {
  std::vector<char*> args;
  std::vector<std::string> settings = {"Threads=1"};
  for (int a = 0; a < argCount; ++a) {
    if (a > 0 && std::string(arguments[a]).find('=') != std::string::npos) settings.push_back(arguments[a]);
    else args.push_back(arguments[a]);
  }
  const int argc = int(args.size());
  char** argv = args.data();
  if (argc < 12 || (argc - 7) % 5 != 0) {
    std::fprintf(stderr, "usage: EmbedConsumer CAMERAS WIDTH HEIGHT FRAMES VIRTUAL OUT {NAME ZNEAR ZFAR TEXTURE DEPTH}...\n");
    return 2;
  }
  try {
    const vs::CameraFile cameras = vs::readCameraFile(argv[1]);
    vs::EmbeddedScene scene;
    scene.texture = vs::FrameFormat{std::atoi(argv[2]), std::atoi(argv[3]), 8, vs::ChromaFormat::Yuv420};
    scene.depthBitDepth = 8;
    const int frames = std::atoi(argv[4]);
    scene.virtualCamera = cameras.find(argv[5]);
    scene.settings = settings;
    std::vector<vs::YuvReader> textures, depths;
    for (int a = 7; a + 4 < argc; a += 5) {
      vs::EmbeddedView view;
      view.camera = cameras.find(argv[a]);
      view.znear = std::strtod(argv[a + 1], nullptr);
      view.zfar = std::strtod(argv[a + 2], nullptr);
      scene.references.push_back(view);
      textures.emplace_back(argv[a + 3], scene.texture);
      depths.emplace_back(argv[a + 4], scene.texture);
    }
    vs::ViewSynthesizer synthesizer(scene);
    for (const std::string& line : synthesizer.plan()) std::printf("plan: %s\n", line.c_str());
    vs::YuvWriter writer(argv[6], scene.texture);
    const size_t n = scene.references.size();
    std::vector<vs::Frame> texture(n);
    std::vector<vs::Plane> depth(n);
    vs::Frame output;
    for (int f = 0; f < frames; ++f) {
      std::vector<vs::ReferenceFrame> references(n);
      for (size_t k = 0; k < n; ++k) {
        textures[k].read(f, texture[k]);
        depths[k].readLuma(f, depth[k]);
        references[k] = vs::ReferenceFrame{&texture[k], &depth[k]};
      }
      synthesizer.synthesize(references, output);
      writer.append(output);
    }
    writer.commit();  // the file is renamed into place only once it is whole
    std::printf("%d frames synthesized in memory\n", frames);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "EmbedConsumer: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
