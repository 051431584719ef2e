#pragma once
// Small double-precision 3-vectors and 3x3 matrices for camera geometry. Everything that composes
// camera matrices works in double (../shared/DESIGN.md, "Depth").
#include <cmath>

#include "Common/Error.h"

namespace vs {

struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }

  Vec3& operator+=(const Vec3& b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
  Vec3& operator-=(const Vec3& b) {
    x -= b.x;
    y -= b.y;
    z -= b.z;
    return *this;
  }
  Vec3& operator*=(double s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(const Vec3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(double s, const Vec3& a) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator/(const Vec3& a, double s) { return {a.x / s, a.y / s, a.z / s}; }
inline bool operator==(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
inline bool operator!=(const Vec3& a, const Vec3& b) { return !(a == b); }

inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline bool isFinite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// Row-major 3x3 matrix: m[row][col]; M[r][c] reads the same way.
struct Mat3 {
  double m[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};

  static constexpr Mat3 identity() {
    Mat3 a;
    a.m[0][0] = a.m[1][1] = a.m[2][2] = 1.0;
    return a;
  }
  static constexpr Mat3 zero() { return Mat3(); }

  double* operator[](int row) { return m[row]; }
  const double* operator[](int row) const { return m[row]; }

  Vec3 row(int r) const { return {m[r][0], m[r][1], m[r][2]}; }
  Vec3 col(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
};

inline Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c.m[r][k] = a.m[r][0] * b.m[0][k] + a.m[r][1] * b.m[1][k] + a.m[r][2] * b.m[2][k];
  return c;
}
inline Vec3 operator*(const Mat3& a, const Vec3& v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z, a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
inline Mat3 operator*(const Mat3& a, double s) {
  Mat3 c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c.m[r][k] = a.m[r][k] * s;
  return c;
}
inline Mat3 operator*(double s, const Mat3& a) { return a * s; }
inline Mat3 operator+(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c.m[r][k] = a.m[r][k] + b.m[r][k];
  return c;
}
inline Mat3 operator-(const Mat3& a, const Mat3& b) {
  Mat3 c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c.m[r][k] = a.m[r][k] - b.m[r][k];
  return c;
}
inline bool operator==(const Mat3& a, const Mat3& b) {
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      if (a.m[r][k] != b.m[r][k]) return false;
  return true;
}
inline bool operator!=(const Mat3& a, const Mat3& b) { return !(a == b); }

inline Mat3 transpose(const Mat3& a) {
  Mat3 t;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) t.m[r][k] = a.m[k][r];
  return t;
}

inline double determinant(const Mat3& a) {
  return a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) -
         a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0]) +
         a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
}

// Largest absolute entry (the max norm), used for "how far from" checks.
inline double maxAbs(const Mat3& a) {
  double v = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) v = std::fmax(v, std::fabs(a.m[r][k]));
  return v;
}

inline bool isFinite(const Mat3& a) {
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(a.m[r][k])) return false;
  return true;
}

// Frobenius norm.
inline double norm(const Mat3& a) {
  double s = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) s += a.m[r][k] * a.m[r][k];
  return std::sqrt(s);
}

// Inverse by the adjugate. The caller makes sure the matrix is invertible (validateCamera refuses a
// singular K as bad input); a zero determinant here is a bug.
inline Mat3 inverse(const Mat3& a) {
  const double det = determinant(a);
  VS_CHECK_MSG(det != 0.0 && std::isfinite(det), "inverse of a singular 3x3 matrix");
  Mat3 b;
  b.m[0][0] = a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1];
  b.m[0][1] = a.m[0][2] * a.m[2][1] - a.m[0][1] * a.m[2][2];
  b.m[0][2] = a.m[0][1] * a.m[1][2] - a.m[0][2] * a.m[1][1];
  b.m[1][0] = a.m[1][2] * a.m[2][0] - a.m[1][0] * a.m[2][2];
  b.m[1][1] = a.m[0][0] * a.m[2][2] - a.m[0][2] * a.m[2][0];
  b.m[1][2] = a.m[0][2] * a.m[1][0] - a.m[0][0] * a.m[1][2];
  b.m[2][0] = a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0];
  b.m[2][1] = a.m[0][1] * a.m[2][0] - a.m[0][0] * a.m[2][1];
  b.m[2][2] = a.m[0][0] * a.m[1][1] - a.m[0][1] * a.m[1][0];
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) b.m[r][k] /= det;
  return b;
}

}  // namespace vs
