#include "Scene/RayCaster.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "Common/Error.h"

namespace vs {

PlacedScene::PlacedScene(const std::vector<Primitive>& primitives, double frame, double motionScale) {
  placed_.reserve(primitives.size());
  for (const Primitive& primitive : primitives) placed_.push_back(placePrimitive(primitive, frame, motionScale));
}

namespace {

// Unit surface normal at a hit point in the object's frame (box hits lie exactly on a face).
Vec3 objectNormal(Shape shape, const Vec3& halfSize, const Vec3& p) {
  switch (shape) {
    case Shape::Rectangle:
      return {0.0, 0.0, 1.0};
    case Shape::Sphere:
      return p / halfSize.x;
    case Shape::Box:
      for (int axis = 0; axis < 3; ++axis)
        if (std::fabs(p[axis]) == halfSize[axis]) {
          Vec3 n;
          n[axis] = 1.0;
          return n;
        }
      break;
  }
  return {0.0, 0.0, 1.0};
}

}  // namespace

bool PlacedScene::cast(const Vec3& origin, const Vec3& direction, double tMin, double& t, Rgb* colour,
                       double pixelScale) const {
  const double directionSquared = dot(direction, direction);
  double nearest = std::numeric_limits<double>::infinity();
  const PlacedPrimitive* nearestPrimitive = nullptr;
  Vec3 nearestPoint;
  for (const PlacedPrimitive& placed : placed_) {
    const Vec3 toCentre = placed.centre - origin;
    // Skip primitives whose bounding sphere the ray misses: |toCentre x d|^2 / |d|^2 > r^2.
    const Vec3 c = cross(toCentre, direction);
    const double r2 = placed.boundingRadius * placed.boundingRadius;
    if (dot(c, c) > r2 * directionSquared) continue;
    const Vec3 objectOrigin = placed.worldToObject * (origin - placed.centre);
    const Vec3 objectDirection = placed.worldToObject * direction;
    double hitT = 0.0;
    Vec3 point;
    if (intersectObject(placed.primitive->shape, placed.primitive->halfSize, objectOrigin, objectDirection, tMin,
                        nearest, hitT, point)) {
      nearest = hitT;
      nearestPrimitive = &placed;
      nearestPoint = point;
    }
  }
  if (!nearestPrimitive) return false;
  t = nearest;
  if (colour) {
    const Primitive& hit = *nearestPrimitive->primitive;
    double footprint = 0.0;
    if (pixelScale > 0.0) {
      // A pixel stretches by 1 / cos along the tilt of an oblique surface; the geometric mean of the
      // two axes keeps the isotropic filter from blurring the other one too much.
      const Vec3 objectDirection = nearestPrimitive->worldToObject * direction;
      const double cosine = std::fabs(dot(objectNormal(hit.shape, hit.halfSize, nearestPoint), objectDirection)) /
                            std::sqrt(directionSquared);
      footprint = nearest * pixelScale / std::sqrt(std::max(cosine, 0.05));
    }
    *colour = hit.texture.colourAt(nearestPoint, footprint);
  }
  return true;
}

std::vector<std::pair<double, double>> subPixelOffsets(int samplesPerPixel) {
  switch (samplesPerPixel) {
    case 1:
      return {{0.0, 0.0}};
    case 4:  // rotated grid: four distinct rows and columns
      return {{0.125, -0.375}, {0.375, 0.125}, {-0.125, 0.375}, {-0.375, -0.125}};
    case 16: {
      std::vector<std::pair<double, double>> offsets;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) offsets.emplace_back((i + 0.5) / 4.0 - 0.5, (j + 0.5) / 4.0 - 0.5);
      return offsets;
    }
    default:
      break;
  }
  VS_CHECK_MSG(false, "samples per pixel must be 1, 4 or 16");
  return {};
}

void forEachRow(int rows, int threads, const std::function<void(int)>& rowFunction) {
  int workers = threads > 0 ? threads : int(std::thread::hardware_concurrency());
  workers = std::clamp(workers, 1, std::max(1, rows));
  std::atomic<int> nextRow{0};
  auto work = [&]() {
    for (int row = nextRow++; row < rows; row = nextRow++) rowFunction(row);
  };
  if (workers == 1) {
    work();
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(size_t(workers - 1));
  for (int i = 1; i < workers; ++i) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
}

namespace {

// World ray of a pixel position from the camera centre: R^-1 K^-1 (u, v, 1) for a pinhole camera,
// whose camera-frame z is 1, so the ray parameter t of a hit is its camera-frame z; the unit ray
// for an equirectangular one, so t is the distance along the ray (MPEG-I's ERP depth).
struct CameraRays {
  explicit CameraRays(const Camera& camera) : camera_(camera), cameraToWorld_(inverse(camera.R)) {}
  Vec3 direction(double u, double v) const { return cameraToWorld_ * camera_.rayCamera(u, v); }
  const Vec3& origin() const { return camera_.t; }
  // World size of a pixel per unit of t: 1 / focal length, or the angle of a column (ERP).
  double pixelScale() const {
    if (camera_.isEquirectangular())
      return (camera_.erp.lonMax - camera_.erp.lonMin) * (M_PI / 180.0) / camera_.erp.width;
    return 1.0 / std::sqrt(camera_.K[0][0] * camera_.K[1][1]);
  }

 private:
  const Camera& camera_;
  Mat3 cameraToWorld_;
};

// Hits closer than this (in camera z) are ignored: nothing sits on the camera centre.
constexpr double kMinDepth = 1e-9;

}  // namespace

RenderedView renderView(const std::vector<Primitive>& primitives, const Camera& camera, int width, int height,
                        int frame, const RenderOptions& options) {
  RenderedView view;
  view.width = width;
  view.height = height;
  view.colour.assign(size_t(width) * size_t(height), Rgb{});
  view.depth.assign(size_t(width) * size_t(height), kNoSurface);
  const PlacedScene scene(primitives, double(frame), options.motionScale);
  const CameraRays rays(camera);
  const std::vector<std::pair<double, double>> offsets = subPixelOffsets(options.samplesPerPixel);
  const float weight = 1.0f / float(offsets.size());
  forEachRow(height, options.threads, [&](int v) {
    Rgb* colourRow = view.colour.data() + size_t(v) * size_t(width);
    double* depthRow = view.depth.data() + size_t(v) * size_t(width);
    for (int u = 0; u < width; ++u) {
      double t = 0.0;
      if (scene.cast(rays.origin(), rays.direction(u, v), kMinDepth, t, nullptr)) depthRow[u] = t;
      Rgb sum;
      for (const auto& [du, dv] : offsets) {
        Rgb sample;  // black where the ray hits nothing
        scene.cast(rays.origin(), rays.direction(u + du, v + dv), kMinDepth, t, &sample, rays.pixelScale());
        sum.r += sample.r;
        sum.g += sample.g;
        sum.b += sample.b;
      }
      colourRow[u] = {sum.r * weight, sum.g * weight, sum.b * weight};
    }
  });
  return view;
}

std::vector<double> renderDepth(const std::vector<Primitive>& primitives, const Camera& camera, int width, int height,
                                int frame, const RenderOptions& options) {
  std::vector<double> depth(size_t(width) * size_t(height), kNoSurface);
  const PlacedScene scene(primitives, double(frame), options.motionScale);
  const CameraRays rays(camera);
  forEachRow(height, options.threads, [&](int v) {
    double* depthRow = depth.data() + size_t(v) * size_t(width);
    for (int u = 0; u < width; ++u) {
      double t = 0.0;
      if (scene.cast(rays.origin(), rays.direction(u, v), kMinDepth, t, nullptr)) depthRow[u] = t;
    }
  });
  return depth;
}

}  // namespace vs
