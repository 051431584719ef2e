#include "Scene/Texture.h"

#include <algorithm>
#include <cmath>

namespace vs {

namespace {

// Integer hash of a lattice point (a variant of the lowbias32 mixer): well spread, portable.
uint32_t hashLattice(int64_t x, int64_t y, int64_t z, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B9u;
  h ^= uint32_t(x) * 0x85EBCA6Bu;
  h = (h << 13) | (h >> 19);
  h ^= uint32_t(y) * 0xC2B2AE35u;
  h = (h << 13) | (h >> 19);
  h ^= uint32_t(z) * 0x27D4EB2Fu;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

double latticeValue(int64_t x, int64_t y, int64_t z, uint32_t seed) {
  return double(hashLattice(x, y, z, seed) >> 8) * (1.0 / 16777215.0);
}

double smoothstep(double t) { return t * t * (3.0 - 2.0 * t); }

// floor() as an integer; the offsets below keep lattice and cell planes off the faces of primitives
// so that rounding noise in a hit point cannot flip a cell.
int64_t floorToInt(double v) { return int64_t(std::floor(v)); }

// Irrational-looking offsets: a box face at a multiple of the cell size would otherwise sit exactly on
// a cell boundary.
constexpr double kCellOffset[3] = {0.1234567, 0.3456789, 0.2345678};

}  // namespace

double valueNoise(const Vec3& p, uint32_t seed) {
  const int64_t ix = floorToInt(p.x), iy = floorToInt(p.y), iz = floorToInt(p.z);
  const double fx = smoothstep(p.x - double(ix)), fy = smoothstep(p.y - double(iy)), fz = smoothstep(p.z - double(iz));
  double corner[8];
  for (int k = 0; k < 8; ++k) corner[k] = latticeValue(ix + (k & 1), iy + ((k >> 1) & 1), iz + ((k >> 2) & 1), seed);
  const double x00 = corner[0] + (corner[1] - corner[0]) * fx;
  const double x10 = corner[2] + (corner[3] - corner[2]) * fx;
  const double x01 = corner[4] + (corner[5] - corner[4]) * fx;
  const double x11 = corner[6] + (corner[7] - corner[6]) * fx;
  const double y0 = x00 + (x10 - x00) * fy;
  const double y1 = x01 + (x11 - x01) * fy;
  return y0 + (y1 - y0) * fz;
}

double detailVisibility(double period, double footprint) {
  if (footprint <= 0.0) return 1.0;
  return std::clamp((period / footprint - 2.0) / 2.0, 0.0, 1.0);
}

double fractalNoise(const Vec3& p, int octaves, uint32_t seed, double footprint) {
  double sum = 0.0, amplitude = 1.0, total = 0.0, frequency = 1.0;
  for (int octave = 0; octave < octaves; ++octave) {
    const double visibility = detailVisibility(1.0 / frequency, footprint);
    const double value = visibility > 0.0 ? valueNoise(p * frequency, seed + uint32_t(octave) * 101u) : 0.5;
    sum += amplitude * (0.5 + visibility * (value - 0.5));
    total += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  return total > 0.0 ? sum / total : 0.5;
}

Rgb Texture::colourAt(const Vec3& p, double footprint) const {
  double w = 0.0;  // 0: colourA, 1: colourB
  // Hard-edged patterns fade to the mean of their two colours as their period nears two pixels.
  auto hardEdged = [&](int64_t parity, double period) {
    return 0.5 + (double(parity & 1) - 0.5) * detailVisibility(period, footprint);
  };
  switch (pattern) {
    case Pattern::Flat:
      break;
    case Pattern::Checker: {
      const int64_t cx = floorToInt(p.x / scale + kCellOffset[0]);
      const int64_t cy = floorToInt(p.y / scale + kCellOffset[1]);
      const int64_t cz = floorToInt(p.z / scale + kCellOffset[2]);
      w = hardEdged(cx + cy + cz, 2.0 * scale);
      break;
    }
    case Pattern::Stripes: {
      const int64_t band = floorToInt(dot(p, bandDirection) / bandWidth + kCellOffset[1]);
      const double period = scale / double(int64_t(1) << ((band % 3 + 3) % 3));
      w = hardEdged(floorToInt(2.0 * dot(p, direction) / period + kCellOffset[0]), period);
      break;
    }
    case Pattern::Noise:
      w = fractalNoise(p / scale, octaves, seed, footprint / scale);
      break;
    case Pattern::Gradient:
      w = std::clamp(dot(p, direction) / scale + 0.5, 0.0, 1.0);
      break;
    case Pattern::Rings: {
      const double radius = std::sqrt(p.x * p.x + p.y * p.y);
      w = hardEdged(floorToInt(2.0 * radius / scale + kCellOffset[2]), scale);
      break;
    }
  }
  Rgb colour = mix(colourA, colourB, float(w));
  if (detail > 0.0) {
    // Brightness modulation by three octaves of fine noise: surfaces never look flat, which is what
    // real camera pictures look like and what makes matching and warping errors visible.
    const double n = fractalNoise(p / detailScale, 3, seed ^ 0xA5A5A5u, footprint / detailScale);
    const float gain = float(1.0 + detail * (n - 0.5) * 2.0);
    colour = {std::clamp(colour.r * gain, 0.0f, 1.0f), std::clamp(colour.g * gain, 0.0f, 1.0f),
              std::clamp(colour.b * gain, 0.0f, 1.0f)};
  }
  return colour;
}

}  // namespace vs
