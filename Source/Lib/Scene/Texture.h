#pragma once
// Procedural textures for SceneGen's analytic scenes (doc/scenegen.md). A texture is a function of the
// 3D point in the object's own frame (a solid texture), so it moves and turns with its object and needs
// no surface parametrisation: a rectangle shows the z = 0 slice, a box its face slices, a sphere its
// shell. Colours are RGB in [0, 1], later turned into BT.601 YCbCr.
#include <cstdint>

#include "Common/Geometry.h"

namespace vs {

struct Rgb {
  float r = 0.0f;
  float g = 0.0f;
  float b = 0.0f;
};

inline Rgb mix(const Rgb& a, const Rgb& b, float w) {
  return {a.r + (b.r - a.r) * w, a.g + (b.g - a.g) * w, a.b + (b.b - a.b) * w};
}

enum class Pattern {
  Flat,      // colourA everywhere (plus detail noise)
  Checker,   // 3D checkerboard of cell `scale`: hard edges
  Stripes,   // square-wave stripes across `direction`; the period halves from band to band (bands of
             // width `bandWidth` along `bandDirection`): scale, scale/2, scale/4, then again
  Noise,     // fractal value noise, `octaves` octaves, lowest period `scale`
  Gradient,  // smooth ramp from colourA to colourB over `scale` along `direction`, centred on 0
  Rings,     // concentric square-wave rings around the object's z axis with period `scale`
};

struct Texture {
  Pattern pattern = Pattern::Flat;
  Rgb colourA{0.5f, 0.5f, 0.5f};
  Rgb colourB{0.5f, 0.5f, 0.5f};
  double scale = 1.0;                 // period or cell size in world units (object frame)
  Vec3 direction{1.0, 0.0, 0.0};      // Stripes, Gradient: unit vector across the stripes / along the ramp
  Vec3 bandDirection{0.0, 1.0, 0.0};  // Stripes: unit vector along which the stripe period changes
  double bandWidth = 1.0;             // Stripes: width of one band of constant period
  int octaves = 4;                    // Noise: each octave halves the period and the amplitude
  double detail = 0.0;                // 0..1: strength of fine value noise modulating the brightness
  double detailScale = 0.05;          // period of the finest detail noise octave's base
  uint32_t seed = 1;                  // Noise and detail: which noise field

  // The colour at `p`, a point in the object's frame, seen through a pixel of world size `footprint`
  // there (0: unfiltered). Detail finer than about two pixels fades to its mean, as a camera's pixel
  // integration would blur it: the ground truth stays free of aliasing that no view synthesis could
  // reproduce.
  Rgb colourAt(const Vec3& p, double footprint = 0.0) const;
};

// Smooth value noise in [0, 1] with period-1 lattice: trilinear blend (smoothstep weights) of hashed
// lattice values. Deterministic for a given seed on every platform.
double valueNoise(const Vec3& p, uint32_t seed);
// Sum of `octaves` octaves of valueNoise, each of half the period and half the amplitude of the one
// before, normalised back to [0, 1]. `footprint` is the pixel size in units of the first octave's
// period: octaves of fewer than 4 pixels a period fade to their mean (0.5), gone at 2 pixels.
double fractalNoise(const Vec3& p, int octaves, uint32_t seed, double footprint = 0.0);

// How much of a pattern of period `period` a pixel of size `footprint` keeps: 1 at 4 or more pixels
// a period, 0 at 2 or fewer (Nyquist), linear between; 1 when footprint is 0.
double detailVisibility(double period, double footprint);

}  // namespace vs
