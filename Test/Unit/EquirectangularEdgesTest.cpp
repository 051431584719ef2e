// The edges of equirectangular (ERP) pictures: reading a full-circle reference's texture round its
// longitude wrap and across its poles (Synth/Interpolation.h's SphereEdges), against a texture that is
// an analytic function of the direction, written out here independently of Camera.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "Common/CameraJson.h"
#include "ErpTestCameras.h"
#include "Plan/Plan.h"
#include "StabilityScene.h"
#include "Synth/Interpolation.h"

namespace vs {
namespace {

using test::erpPixelDirection;
using test::sphereChroma;
using test::sphereDirection;
using test::sphereLuma;
using test::sphereTexture;

using test::kPi;


TEST(EquirectangularEdges, SamplerReadsRoundTheWrapAndAcrossThePoles) {
  const int width = 128, height = 64;
  const Plane plane = sphereTexture(width, height, sphereLuma, 1.0);
  const SphereEdges sphere{true, true, true};
  for (int filter : {0, 1, 2}) {
    const SubPixelSampler sampler(4, filter);
    // Inside, the same bits as the plain sampler.
    for (double y = 4.0; y <= height - 5.0; y += 1.75)
      for (double x = 4.0; x <= width - 5.0; x += 2.25)
        ASSERT_EQ(sampler.sample(plane, x, y), sampler.withTaps([&](auto taps) {
          return sampler.sampleSphereTaps<decltype(taps)::value>(plane, x, y, sphere);
        })) << filter;
    // Within half a sample of the wrap and of the poles (quarter-pel positions: no rounding), against
    // the function there; the plain sampler, which reads the edge sample, is far off.
    double worst = 0, worstClamped = 0;
    const auto check = [&](double x, double y) {
      const double truth = sphereLuma(erpPixelDirection(x, y, width, height));
      const float value = sampler.withTaps([&](auto taps) {
        return sampler.sampleSphereTaps<decltype(taps)::value>(plane, x, y, sphere);
      });
      worst = std::max(worst, std::fabs(value - truth));
      worstClamped = std::max(worstClamped, std::fabs(sampler.sample(plane, x, y) - truth));
    };
    for (double y = 0; y < height; y += 1.0)
      for (double x : {-0.5, -0.25, 0.25, width - 1.25, width - 0.75}) check(x, y);
    for (double x = -0.5; x < width - 0.5; x += 0.75)
      for (double y : {-0.5, -0.25, height - 0.75, height - 0.5}) check(x, y);
    test::recordFigure("worst_error_filter" + std::to_string(filter), worst);
    test::recordFigure("worst_error_clamped_filter" + std::to_string(filter), worstClamped);
    EXPECT_LE(worst, filter == 0 ? 2.0 : 1.0) << "filter " << filter;
    EXPECT_GE(worstClamped, 5.0) << "filter " << filter;
  }
  // A partial circle is clamped: the same as the plain sampler everywhere.
  const SubPixelSampler sampler(4, 1);
  for (double y = -0.5; y < height; y += 3.25)
    for (double x : {-0.5, -0.25, 0.5, width - 0.75})
      EXPECT_EQ(sampler.sample(plane, x, y), sampler.sampleSphereTaps<4>(plane, x, y, SphereEdges{}));
}

// A full-sphere ERP reference at the origin of constant distance, the texture above on it, synthesized
// into ERP virtual cameras at the same centre turned by fractions of a sample (every look-up between
// samples; the wrap column's across the wrap, the pole rows' across the pole): each output sample is
// the function at its own direction, up to the interpolation, rounding to quarter pel and 8 bits.
TEST(EquirectangularEdges, ReferenceTextureIsReadRoundTheWrapAndAcrossThePoles) {
  const int width = 128, height = 64;
  const Camera reference = test::erpCamera("reference", width, height, Vec3(0, 0, 0));
  const FrameFormat format{width, height, 8, ChromaFormat::Yuv420};
  test::SynthesisInputs inputs;
  inputs.textures.emplace_back(format);
  inputs.textures[0].planes[0] = sphereTexture(width, height, sphereLuma, 1.0);
  inputs.textures[0].planes[1] = sphereTexture(width / 2, height / 2, sphereChroma, 0.5);
  inputs.textures[0].planes[2] = Plane(width / 2, height / 2, 128);
  const DepthRange range{1.0, 10.0, 8};
  inputs.depths.emplace_back(width, height, uint16_t(255));  // distance 1 everywhere
  const double sample = 360.0 / width;
  for (const auto& [yaw, pitch] : {std::pair{0.5 * sample, 0.0}, std::pair{0.3 * sample, 0.45 * sample},
                                   std::pair{-0.4 * sample, -0.55 * sample}}) {
    Camera turned = reference;
    turned.name = "turned";
    turned.R = rotationFromYawPitchRoll(yaw, pitch, 0);
    const Scene scene = test::makeScene({reference}, turned, format, range);
    const Frame output = test::synthesize(scene, inputs).output;
    // The direction of a virtual sample in the reference's (the world's) axes: R^T times its ray.
    const auto worldDirection = [&](double u, double v) {
      const Vec3 ray = erpPixelDirection(u, v, width, height);
      const Mat3& r = turned.R;
      return Vec3(r[0][0] * ray.x + r[1][0] * ray.y + r[2][0] * ray.z,
                  r[0][1] * ray.x + r[1][1] * ray.y + r[2][1] * ray.z,
                  r[0][2] * ray.x + r[1][2] * ray.y + r[2][2] * ray.z);
    };
    double wrapWorst = 0, poleWorst = 0, chromaWorst = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double error = std::fabs(output.planes[0].at(x, y) - sphereLuma(worldDirection(x, y)));
        if (x < 2 || x >= width - 2) wrapWorst = std::max(wrapWorst, error);
        if (y < 2 || y >= height - 2) poleWorst = std::max(poleWorst, error);
      }
    for (int y = 0; y < height / 2; ++y)
      for (int x = 0; x < width / 2; ++x)
        if (x == 0 || x == width / 2 - 1 || y == 0 || y == height / 2 - 1)
          chromaWorst = std::max(chromaWorst, std::fabs(output.planes[1].at(x, y) -
                                                        sphereChroma(worldDirection(2 * x + 0.5, 2 * y + 0.5))));
    const std::string turn = std::to_string(int(std::lround(pitch / sample * 100)));
    test::recordFigure("wrap_columns_worst_error_pitch" + turn, wrapWorst);
    test::recordFigure("pole_rows_worst_error_pitch" + turn, poleWorst);
    test::recordFigure("chroma_edge_worst_error_pitch" + turn, chromaWorst);
    EXPECT_LE(wrapWorst, 3.0) << "yaw " << yaw << " pitch " << pitch;
    EXPECT_LE(poleWorst, 4.0) << "yaw " << yaw << " pitch " << pitch;
    EXPECT_LE(chromaWorst, 4.0) << "yaw " << yaw << " pitch " << pitch;
  }
}

}  // namespace
}  // namespace vs
