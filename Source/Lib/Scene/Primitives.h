#pragma once
// Analytic primitives of SceneGen's scenes: rectangles (finite planes), boxes and spheres, each with a
// pose, a solid texture and a per-frame motion. Ray intersection is exact (closed form), done in the
// object's own frame.
#include <string>
#include <vector>

#include "Common/Geometry.h"
#include "Scene/Texture.h"

namespace vs {

enum class Shape {
  Rectangle,  // the part |x| <= halfSize.x, |y| <= halfSize.y of the object's plane z = 0; two-sided
  Box,        // |x| <= halfSize.x, |y| <= halfSize.y, |z| <= halfSize.z
  Sphere,     // |p| <= halfSize.x (the radius)
};

const char* shapeName(Shape shape);

// Motion per frame: the object's centre moves by `velocity` and the object turns about `spinAxis`
// (through its centre, in world coordinates) by `spinDegrees` every frame.
struct Motion {
  Vec3 velocity;
  Vec3 spinAxis{0.0, 1.0, 0.0};
  double spinDegrees = 0.0;

  bool isStatic() const { return velocity == Vec3() && spinDegrees == 0.0; }
};

struct Primitive {
  std::string name;
  Shape shape = Shape::Sphere;
  Vec3 halfSize{0.5, 0.5, 0.5};         // half extents; a sphere's radius is halfSize.x
  Vec3 position;                        // centre in world coordinates at frame 0
  Mat3 orientation = Mat3::identity();  // object -> world rotation at frame 0 (columns: object axes)
  Texture texture;
  Motion motion;
};

// Rotation by `degrees` about `axis` (any length > 0), right-handed (Rodrigues).
Mat3 axisAngleRotation(const Vec3& axis, double degrees);

// A primitive placed at one frame, ready for ray casting: world -> object rotation and centre, plus a
// bounding sphere to skip rays that pass far away.
struct PlacedPrimitive {
  const Primitive* primitive = nullptr;
  Mat3 worldToObject = Mat3::identity();
  Vec3 centre;
  double boundingRadius = 0.0;
};

// The primitive's pose at `frame` (frame 0: the pose as given). `motionScale` multiplies the motion
// (0: static scene).
PlacedPrimitive placePrimitive(const Primitive& primitive, double frame, double motionScale = 1.0);

// Nearest intersection with t in (tMin, tMax) of the ray origin + t * direction, both given in the
// object's frame (direction need not be unit length; t is in its units). On a hit sets t and the hit
// point in the object frame (snapped onto the surface for planar faces) and returns true.
bool intersectObject(Shape shape, const Vec3& halfSize, const Vec3& origin, const Vec3& direction, double tMin,
                     double tMax, double& t, Vec3& objectPoint);

}  // namespace vs
