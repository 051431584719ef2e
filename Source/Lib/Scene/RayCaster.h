#pragma once
// Ray casting of analytic scenes: SceneGen's ground truth. Depth is the camera-frame z of the nearest
// surface on the pixel centre's ray (for an equirectangular camera: its distance along the ray); colour
// is the mean of a few sub-pixel rays (anti-aliasing), each finding its own nearest surface, so object
// edges blend as a real camera would blur them.
#include <functional>
#include <limits>
#include <vector>

#include "Common/Camera.h"
#include "Scene/Primitives.h"

namespace vs {

// The primitives of a scene placed at one frame: answers "what does this ray hit first".
class PlacedScene {
 public:
  PlacedScene(const std::vector<Primitive>& primitives, double frame, double motionScale = 1.0);

  // Nearest surface along origin + t * direction with t > tMin (direction any length > 0). Returns
  // false when the ray hits nothing; otherwise sets t and, when `colour` is given, the surface colour.
  // `pixelScale` is the world size of a pixel per unit of t on a surface facing the ray (for a camera
  // ray whose camera-frame z is 1: 1 / focal length); the texture is filtered to that pixel size, 0
  // leaves it unfiltered.
  bool cast(const Vec3& origin, const Vec3& direction, double tMin, double& t, Rgb* colour,
            double pixelScale = 0.0) const;

 private:
  std::vector<PlacedPrimitive> placed_;
};

// Sub-pixel sample offsets from the pixel centre, in pixels: 1 (the centre), 4 (rotated grid) or 16
// (4 x 4 grid). Anything else is a bug.
std::vector<std::pair<double, double>> subPixelOffsets(int samplesPerPixel);

struct RenderOptions {
  int samplesPerPixel = 4;   // colour rays per pixel: 1, 4 or 16
  int threads = 0;           // 0: every core
  double motionScale = 1.0;  // multiplies every object's motion (0: a static scene)
};

// Colour (RGB in [0, 1], the background black where no ray hits) and depth (camera-frame z of the
// centre ray's surface, or its distance for ERP; +inf where it hits nothing) of one camera at one
// frame, row-major.
struct RenderedView {
  int width = 0;
  int height = 0;
  std::vector<Rgb> colour;
  std::vector<double> depth;

  const Rgb& colourAt(int u, int v) const { return colour[size_t(v) * size_t(width) + size_t(u)]; }
  double depthAt(int u, int v) const { return depth[size_t(v) * size_t(width) + size_t(u)]; }
};

constexpr double kNoSurface = std::numeric_limits<double>::infinity();

RenderedView renderView(const std::vector<Primitive>& primitives, const Camera& camera, int width, int height,
                        int frame, const RenderOptions& options);

// Depth only (centre rays, no colour): for the automatic depth range. Same values as renderView's.
std::vector<double> renderDepth(const std::vector<Primitive>& primitives, const Camera& camera, int width, int height,
                                int frame, const RenderOptions& options);

// Calls rowFunction(row) for every row in [0, rows) on `threads` threads (0: every core), rows handed
// out one by one so that uneven rows balance.
void forEachRow(int rows, int threads, const std::function<void(int)>& rowFunction);

}  // namespace vs
