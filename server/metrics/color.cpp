#include "metrics/color.h"

#include <cmath>

namespace ddgi::metrics {

namespace {

// sRGB primaries and D65 white (IEC 61966-2-1), linear RGB -> XYZ.
constexpr double kRgbToXyz[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                    {0.2126729, 0.7151522, 0.0721750},
                                    {0.0193339, 0.1191920, 0.9503041}};

struct Matrix3 {
  double m[3][3];
};

constexpr Matrix3 inverse(const double (&a)[3][3]) {
  const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                     a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  Matrix3 r{};
  r.m[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
  r.m[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
  r.m[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
  r.m[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) / det;
  r.m[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
  r.m[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
  r.m[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) / det;
  r.m[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
  r.m[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
  return r;
}

// Computed (at compile time) rather than typed in, so the round trip RGB -> XYZ -> RGB is exact to
// rounding.
constexpr Matrix3 kXyzToRgb = inverse(kRgbToXyz);

constexpr Color3 multiply(const double (&m)[3][3], const Color3& v) {
  return {m[0][0] * v.c0 + m[0][1] * v.c1 + m[0][2] * v.c2,
          m[1][0] * v.c0 + m[1][1] * v.c1 + m[1][2] * v.c2,
          m[2][0] * v.c0 + m[2][1] * v.c1 + m[2][2] * v.c2};
}

// Reference white: XYZ of linear RGB (1, 1, 1).
constexpr Color3 kWhite = multiply(kRgbToXyz, {1.0, 1.0, 1.0});

// CIELAB's cube root with its linear toe below (6/29)^3.
double lab_f(double t) {
  constexpr double kDelta = 6.0 / 29.0;
  if (t > kDelta * kDelta * kDelta) return std::cbrt(t);
  return t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
}

}  // namespace

double srgb_to_linear(double encoded) {
  if (encoded <= 0.04045) return encoded / 12.92;
  return std::pow((encoded + 0.055) / 1.055, 2.4);
}

Color3 linear_rgb_to_xyz(const Color3& rgb) {
  return multiply(kRgbToXyz, rgb);
}

Color3 xyz_to_linear_rgb(const Color3& xyz) {
  return multiply(kXyzToRgb.m, xyz);
}

Color3 xyz_to_ycxcz(const Color3& xyz) {
  const double x = xyz.c0 / kWhite.c0;
  const double y = xyz.c1 / kWhite.c1;
  const double z = xyz.c2 / kWhite.c2;
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Color3 ycxcz_to_xyz(const Color3& ycxcz) {
  const double y = (ycxcz.c0 + 16.0) / 116.0;
  const double x = ycxcz.c1 / 500.0 + y;
  const double z = y - ycxcz.c2 / 200.0;
  return {x * kWhite.c0, y * kWhite.c1, z * kWhite.c2};
}

Color3 xyz_to_lab(const Color3& xyz) {
  const double fx = lab_f(xyz.c0 / kWhite.c0);
  const double fy = lab_f(xyz.c1 / kWhite.c1);
  const double fz = lab_f(xyz.c2 / kWhite.c2);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

Color3 hunt_adjust(const Color3& lab) {
  const double scale = 0.01 * lab.c0;
  return {lab.c0, scale * lab.c1, scale * lab.c2};
}

double hyab(const Color3& lab_a, const Color3& lab_b) {
  const double da = lab_a.c1 - lab_b.c1;
  const double db = lab_a.c2 - lab_b.c2;
  return std::abs(lab_a.c0 - lab_b.c0) + std::sqrt(da * da + db * db);
}

}  // namespace ddgi::metrics
