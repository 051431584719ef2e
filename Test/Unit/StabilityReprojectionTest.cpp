// Numerical stability, part 4 (doc/stability.md): reprojection accuracy of the warp itself.
// ViewProjection::forward and ::backward against the analytic projection of ray-cast SceneGen points,
// in the double arithmetic the library uses and in two float variants computed here for comparison:
// the same formulas with the matrices composed in double and then rounded to float, and VSRS's way
// (the world point, then its projection, all in float). The library keeps double: it is the one that
// meets 1e-3 px everywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "StabilityScene.h"
#include "Synth/Warp.h"

namespace vs {
namespace {

using test::GeneratedScene;
using test::recordFigure;

struct Mat3f {
  float m[3][3];
  explicit Mat3f(const Mat3& a) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] = float(a[r][c]);
  }
};
struct Vec3f {
  float x, y, z;
  explicit Vec3f(const Vec3& a) : x(float(a.x)), y(float(a.y)), z(float(a.z)) {}
};

// ViewProjection's general path (Warp.cpp) with float numbers: matrices composed in double as there,
// then rounded; the per-sample arithmetic in float.
class FloatViewProjection {
public:
  FloatViewProjection(const Camera& reference, const Camera& target, int depthType)
      : depthType_(depthType),
        forwardMatrix_(target.K * relativePose(reference, target).R * inverse(reference.K)),
        forwardOffset_(target.K * relativePose(reference, target).t),
        backwardMatrix_(reference.K * inverse(relativePose(reference, target).R) * inverse(target.K)),
        backwardOffset_(-(reference.K * (inverse(relativePose(reference, target).R) * relativePose(reference, target).t))),
        worldRayZ_((inverse(reference.R) * inverse(reference.K)).row(2)),
        centreZ_(float(reference.t.z)) {}

  bool forward(float u, float v, float inverseDepth, float& x, float& y, float& wv) const {
    float a = 1.0f, w = inverseDepth;
    if (depthType_ == 1) {
      const float rayZ = worldRayZ_.x * u + worldRayZ_.y * v + worldRayZ_.z;
      if (rayZ == 0.0f) return false;
      a = (1.0f - w * centreZ_) / rayZ;
    }
    if (w < 0.0f) {
      a = -a;
      w = -w;
    }
    if (!(a > 0.0f)) return false;
    const auto& m = forwardMatrix_.m;
    const float px = a * (m[0][0] * u + m[0][1] * v + m[0][2]) + forwardOffset_.x * w;
    const float py = a * (m[1][0] * u + m[1][1] * v + m[1][2]) + forwardOffset_.y * w;
    const float pz = a * (m[2][0] * u + m[2][1] * v + m[2][2]) + forwardOffset_.z * w;
    if (!(pz > 0.0f)) return false;
    x = px / pz;
    y = py / pz;
    wv = w / pz;
    return std::isfinite(x) && std::isfinite(y);
  }

  bool backward(float x, float y, float wv, float& u, float& v) const {
    const auto& m = backwardMatrix_.m;
    const float qx = m[0][0] * x + m[0][1] * y + m[0][2] + backwardOffset_.x * wv;
    const float qy = m[1][0] * x + m[1][1] * y + m[1][2] + backwardOffset_.y * wv;
    const float qz = m[2][0] * x + m[2][1] * y + m[2][2] + backwardOffset_.z * wv;
    if (!(qz > 0.0f)) return false;
    u = qx / qz;
    v = qy / qz;
    return std::isfinite(u) && std::isfinite(v);
  }

private:
  int depthType_;
  Mat3f forwardMatrix_;
  Vec3f forwardOffset_;
  Mat3f backwardMatrix_;
  Vec3f backwardOffset_;
  Vec3f worldRayZ_;
  float centreZ_;
};

// VSRS's float warp (DepthType 0): world point X = C + R^-1 K^-1 (u, v, 1) z, then K_t R_t (X - C_t).
bool naiveFloatForward(const Camera& reference, const Camera& target, float u, float v, float z, float& x, float& y) {
  const Mat3f rayMatrix(inverse(reference.R) * inverse(reference.K));
  const Mat3f projection(target.K * target.R);
  const Vec3f c(reference.t), ct(target.t);
  const auto& r = rayMatrix.m;
  const float X = c.x + (r[0][0] * u + r[0][1] * v + r[0][2]) * z;
  const float Y = c.y + (r[1][0] * u + r[1][1] * v + r[1][2]) * z;
  const float Z = c.z + (r[2][0] * u + r[2][1] * v + r[2][2]) * z;
  const float dx = X - ct.x, dy = Y - ct.y, dz = Z - ct.z;
  const auto& p = projection.m;
  const float px = p[0][0] * dx + p[0][1] * dy + p[0][2] * dz;
  const float py = p[1][0] * dx + p[1][1] * dy + p[1][2] * dz;
  const float pz = p[2][0] * dx + p[2][1] * dy + p[2][2] * dz;
  if (!(pz > 0.0f)) return false;
  x = px / pz;
  y = py / pz;
  return std::isfinite(x) && std::isfinite(y);
}

struct Errors {
  double sum = 0, max = 0;
  size_t count = 0, failed = 0;  // failed: a valid point the variant did not warp
  void add(double e) {
    sum += e;
    max = std::max(max, e);
    ++count;
  }
  double mean() const { return count ? sum / double(count) : 0.0; }
};

struct Accuracy {
  Errors forwardDouble, backwardDouble, depthDouble, forwardFloat, backwardFloat, forwardNaive;
};

// Casts the reference's pixel centres (every `step`-th) into the scene, projects each hit analytically
// into the target (the unshifted world), and warps it with cameras whose centres are moved by `shift`.
// Only points landing within one image size of the target image count.
Accuracy measure(const GeneratedScene& scene, const Camera& reference, const Camera& target, int depthType,
                 const Vec3& shift, int step) {
  Camera shiftedReference = reference, shiftedTarget = target;
  shiftedReference.t += shift;
  shiftedTarget.t += shift;
  const ViewProjection projection(shiftedReference, shiftedTarget, depthType);
  const FloatViewProjection floatProjection(shiftedReference, shiftedTarget, depthType);
  const PlacedScene placed = scene.placed();
  const Mat3 toWorld = inverse(reference.R);
  const int w = scene.width(), h = scene.height();
  Accuracy a;
  for (int v = 0; v < h; v += step)
    for (int u = 0; u < w; u += step) {
      const Vec3 direction = toWorld * reference.pixelToCamera(u, v, 1.0);  // camera z 1: t is the depth
      double t = 0;
      if (!placed.cast(reference.t, direction, 1e-9, t, nullptr)) continue;
      const Vec3 X = reference.t + direction * t;
      double ax, ay, az;
      if (!target.project(X, ax, ay, az) || ax < -w || ax > 2.0 * w || ay < -h || ay > 2.0 * h) continue;
      const double inverseDepth = 1.0 / (depthType == kDepthTypeWorld ? X.z + shift.z : t);
      double x, y, wv, bu, bv;
      if (projection.forward(u, v, inverseDepth, x, y, wv)) {
        a.forwardDouble.add(std::hypot(x - ax, y - ay));
        a.depthDouble.add(std::fabs(1.0 / wv - az) / az);
      } else {
        ++a.forwardDouble.failed;
      }
      if (projection.backward(ax, ay, 1.0 / az, bu, bv)) a.backwardDouble.add(std::hypot(bu - u, bv - v));
      else ++a.backwardDouble.failed;
      float fx, fy, fw, fu, fv;
      if (floatProjection.forward(float(u), float(v), float(inverseDepth), fx, fy, fw))
        a.forwardFloat.add(std::hypot(double(fx) - ax, double(fy) - ay));
      else
        ++a.forwardFloat.failed;
      if (floatProjection.backward(float(ax), float(ay), float(1.0 / az), fu, fv))
        a.backwardFloat.add(std::hypot(double(fu) - u, double(fv) - v));
      else
        ++a.backwardFloat.failed;
      if (depthType == kDepthTypeCamera) {
        if (naiveFloatForward(shiftedReference, shiftedTarget, float(u), float(v), float(t), fx, fy))
          a.forwardNaive.add(std::hypot(double(fx) - ax, double(fy) - ay));
        else
          ++a.forwardNaive.failed;
      }
    }
  return a;
}

struct PairCase {
  std::string name;
  std::shared_ptr<GeneratedScene> scene;
  Camera reference, target;
  int depthType = kDepthTypeCamera;
  Vec3 shift;
  int step = 1;
};

PairCase pairCase(const std::string& name, const std::shared_ptr<GeneratedScene>& scene, const Camera& reference,
                  const Camera& target, int depthType = kDepthTypeCamera, const Vec3& shift = Vec3(), int step = 1) {
  PairCase c;
  c.name = name;
  c.scene = scene;
  c.reference = reference;
  c.target = target;
  c.depthType = depthType;
  c.shift = shift;
  c.step = step;
  return c;
}

std::vector<PairCase> pairCases() {
  auto tiny = std::make_shared<GeneratedScene>(std::vector<std::string>{"Scene=tiny"});
  auto sphere = std::make_shared<GeneratedScene>(std::vector<std::string>{"Scene=sphere"});
  auto arc = std::make_shared<GeneratedScene>(std::vector<std::string>{"Scene=arc"});  // 640x480, f = 600
  const Camera& a1 = arc->rig()[1];
  const Camera& a3 = arc->rig()[3];
  const Vec3 far(1e6, 1e6, 1e6);
  std::vector<PairCase> cases{
      pairCase("tiny 64x48, cam0 to cam1", tiny, tiny->rig()[0], tiny->rig()[1]),
      pairCase("sphere 160x120, cam0 to cam1", sphere, sphere->rig()[0], sphere->rig()[1]),
      pairCase("arc 640x480, cam1 to cam3 (12 deg)", arc, a1, a3, kDepthTypeCamera, Vec3(), 3),
      pairCase("arc, origin shifted by 1e6", arc, a1, a3, kDepthTypeCamera, far, 3),
      pairCase("arc, DepthType 1", arc, a1, a3, kDepthTypeWorld, Vec3(), 3),
      pairCase("arc, DepthType 1, origin shifted by 1e6", arc, a1, a3, kDepthTypeWorld, far, 3),
  };
  // Skew and a principal point outside the image, on the rotated pair.
  PairCase odd = pairCase("arc, skew 50 px, principal point (-300, 600)", arc, a1, a3, kDepthTypeCamera, Vec3(), 3);
  for (Camera* c : {&odd.reference, &odd.target}) {
    c->K[0][1] = 50;
    c->K[0][2] = -300;
    c->K[1][2] = 600;
  }
  cases.push_back(odd);
  // Focal length 1e6 (a 0.003 degree field of view) with a baseline giving 50 / z px of disparity.
  PairCase narrow = pairCase("tiny, f 1e6, baseline 5e-5", tiny, tiny->rig()[0], tiny->rig()[0]);
  narrow.reference.K[0][0] = narrow.reference.K[1][1] = 1e6;
  narrow.target.K = narrow.reference.K;
  narrow.target.t.x += 5e-5;
  cases.push_back(narrow);
  // Focal length 1e-3 (pixel rays up to 89.998 degrees off the axis): only a near, huge plane fills
  // such a view: SceneGen's plane (half size 1e3) at z = 0.01; a baseline of 100 gives 10 px.
  auto wall = std::make_shared<GeneratedScene>(
      std::vector<std::string>{"Scene=plane", "SourceWidth=64", "SourceHeight=48", "BackgroundDepth=0.01"});
  PairCase wide = pairCase("plane at z 0.01, f 1e-3, baseline 100", wall, wall->rig()[0], wall->rig()[0]);
  wide.reference.K[0][0] = wide.reference.K[1][1] = 1e-3;
  wide.target.K = wide.reference.K;
  wide.target.t.x += 100;
  cases.push_back(wide);
  return cases;
}

TEST(StabilityReprojection, WarpAgreesWithTheAnalyticProjectionToBetterThan1e3PixelInDouble) {
  for (const PairCase& c : pairCases()) {
    const Accuracy a = measure(*c.scene, c.reference, c.target, c.depthType, c.shift, c.step);
    ASSERT_GT(a.forwardDouble.count, 100u) << c.name;
    EXPECT_EQ(a.forwardDouble.failed, 0u) << c.name;
    EXPECT_EQ(a.backwardDouble.failed, 0u) << c.name;
    // Double: far below the 1e-3 px the issue asks for.
    EXPECT_LT(a.forwardDouble.max, 1e-6) << c.name;
    EXPECT_LT(a.backwardDouble.max, 1e-6) << c.name;
    EXPECT_LT(a.depthDouble.max, 1e-9) << c.name;
    recordFigure(c.name + ": points", double(a.forwardDouble.count));
    recordFigure(c.name + ": double forward mean (px)", a.forwardDouble.mean());
    recordFigure(c.name + ": double forward max (px)", a.forwardDouble.max);
    recordFigure(c.name + ": double backward max (px)", a.backwardDouble.max);
    recordFigure(c.name + ": float forward mean (px)", a.forwardFloat.mean());
    recordFigure(c.name + ": float forward max (px)", a.forwardFloat.max);
    recordFigure(c.name + ": float backward max (px)", a.backwardFloat.max);
    recordFigure(c.name + ": float points not warped", double(a.forwardFloat.failed));
    if (c.depthType == kDepthTypeCamera) {
      recordFigure(c.name + ": VSRS-style float forward mean (px)", a.forwardNaive.mean());
      recordFigure(c.name + ": VSRS-style float forward max (px)", a.forwardNaive.max);
    }
  }
}

}  // namespace
}  // namespace vs
