#include "Scene/Primitives.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vs {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

const char* shapeName(Shape shape) {
  switch (shape) {
    case Shape::Rectangle:
      return "rectangle";
    case Shape::Box:
      return "box";
    case Shape::Sphere:
      return "sphere";
  }
  return "?";
}

Mat3 axisAngleRotation(const Vec3& axis, double degrees) {
  const double length = norm(axis);
  VS_CHECK_MSG(length > 0.0, "rotation axis of zero length");
  const Vec3 a = axis / length;
  const double angle = degrees * (kPi / 180.0);
  const double c = std::cos(angle), s = std::sin(angle), C = 1.0 - c;
  Mat3 r;
  r[0][0] = c + a.x * a.x * C;
  r[0][1] = a.x * a.y * C - a.z * s;
  r[0][2] = a.x * a.z * C + a.y * s;
  r[1][0] = a.y * a.x * C + a.z * s;
  r[1][1] = c + a.y * a.y * C;
  r[1][2] = a.y * a.z * C - a.x * s;
  r[2][0] = a.z * a.x * C - a.y * s;
  r[2][1] = a.z * a.y * C + a.x * s;
  r[2][2] = c + a.z * a.z * C;
  return r;
}

PlacedPrimitive placePrimitive(const Primitive& primitive, double frame, double motionScale) {
  PlacedPrimitive placed;
  placed.primitive = &primitive;
  const double steps = frame * motionScale;
  placed.centre = primitive.position + primitive.motion.velocity * steps;
  Mat3 objectToWorld = primitive.orientation;
  if (primitive.motion.spinDegrees != 0.0 && steps != 0.0)
    objectToWorld = axisAngleRotation(primitive.motion.spinAxis, primitive.motion.spinDegrees * steps) * objectToWorld;
  placed.worldToObject = transpose(objectToWorld);
  const Vec3& h = primitive.halfSize;
  switch (primitive.shape) {
    case Shape::Sphere:
      placed.boundingRadius = h.x;
      break;
    case Shape::Rectangle:
      placed.boundingRadius = std::sqrt(h.x * h.x + h.y * h.y);
      break;
    case Shape::Box:
      placed.boundingRadius = norm(h);
      break;
  }
  // A little slack: the bounding test must never reject a ray that grazes the surface.
  placed.boundingRadius *= 1.0 + 1e-9;
  return placed;
}

namespace {

bool intersectRectangle(const Vec3& h, const Vec3& o, const Vec3& d, double tMin, double tMax, double& t, Vec3& p) {
  if (d.z == 0.0) return false;
  const double hitT = -o.z / d.z;
  if (!(hitT > tMin && hitT < tMax)) return false;
  const Vec3 q{o.x + hitT * d.x, o.y + hitT * d.y, 0.0};
  if (std::fabs(q.x) > h.x || std::fabs(q.y) > h.y) return false;
  t = hitT;
  p = q;
  return true;
}

bool intersectBox(const Vec3& h, const Vec3& o, const Vec3& d, double tMin, double tMax, double& t, Vec3& p) {
  double tEnter = -std::numeric_limits<double>::infinity(), tExit = std::numeric_limits<double>::infinity();
  int enterAxis = -1, exitAxis = -1;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) {
      if (std::fabs(o[axis]) > h[axis]) return false;
      continue;
    }
    double t0 = (-h[axis] - o[axis]) / d[axis];
    double t1 = (h[axis] - o[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tEnter) {
      tEnter = t0;
      enterAxis = axis;
    }
    if (t1 < tExit) {
      tExit = t1;
      exitAxis = axis;
    }
  }
  if (tEnter > tExit) return false;
  int axis = -1;
  if (tEnter > tMin && tEnter < tMax) {
    t = tEnter;
    axis = enterAxis;
  } else if (tExit > tMin && tExit < tMax) {  // the ray starts inside the box
    t = tExit;
    axis = exitAxis;
  } else {
    return false;
  }
  p = o + d * t;
  // Snap onto the face: texture cells must not flicker with rounding noise.
  if (axis >= 0) p[axis] = std::copysign(h[axis], p[axis]);
  return true;
}

bool intersectSphere(double radius, const Vec3& o, const Vec3& d, double tMin, double tMax, double& t, Vec3& p) {
  // |o + t d|^2 = r^2  ->  a t^2 + 2 b t + c = 0
  const double a = dot(d, d);
  const double b = dot(o, d);
  const double c = dot(o, o) - radius * radius;
  // b^2 - a c loses digits when the ray is long; the perpendicular distance form keeps them.
  const Vec3 perpendicular = o - d * (b / a);
  const double discriminant = a * (radius * radius - dot(perpendicular, perpendicular));
  if (discriminant < 0.0) return false;
  const double root = std::sqrt(discriminant);
  // Stable roots: q = -(b + sign(b) root); t0 = q / a, t1 = c / q.
  const double q = -(b + std::copysign(root, b));
  double t0 = q / a;
  double t1 = q != 0.0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > tMin && t0 < tMax)
    t = t0;
  else if (t1 > tMin && t1 < tMax)
    t = t1;
  else
    return false;
  p = o + d * t;
  return true;
}

}  // namespace

bool intersectObject(Shape shape, const Vec3& halfSize, const Vec3& origin, const Vec3& direction, double tMin,
                     double tMax, double& t, Vec3& objectPoint) {
  switch (shape) {
    case Shape::Rectangle:
      return intersectRectangle(halfSize, origin, direction, tMin, tMax, t, objectPoint);
    case Shape::Box:
      return intersectBox(halfSize, origin, direction, tMin, tMax, t, objectPoint);
    case Shape::Sphere:
      return intersectSphere(halfSize.x, origin, direction, tMin, tMax, t, objectPoint);
  }
  return false;
}

}  // namespace vs
