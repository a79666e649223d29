// Colour-space conversions FLIP needs: sRGB, linear sRGB, CIE XYZ, YCxCz and CIELAB, all
// relative to the D65 white of the sRGB primaries (the XYZ of linear RGB (1,1,1)).
#pragma once

namespace ddgi::metrics {

struct Color3 {
  double c0 = 0.0;
  double c1 = 0.0;
  double c2 = 0.0;
};

// IEC 61966-2-1 transfer function on one channel in [0,1].
double srgb_to_linear(double encoded);

// Linear sRGB <-> CIE XYZ (sRGB primaries, D65).
Color3 linear_rgb_to_xyz(const Color3& rgb);
Color3 xyz_to_linear_rgb(const Color3& xyz);

// YCxCz (Edwards & Brainard; Johnson & Fairchild): an opponent space that is linear in XYZ, so
// spatial filtering in it is meaningful. Y = 116 Y/Yn - 16, Cx = 500 (X/Xn - Y/Yn),
// Cz = 200 (Y/Yn - Z/Zn). c0 = Y (achromatic), c1 = Cx (red-green), c2 = Cz (blue-yellow).
Color3 xyz_to_ycxcz(const Color3& xyz);
Color3 ycxcz_to_xyz(const Color3& ycxcz);

// CIE 1976 L*a*b*: c0 = L* in [0,100], c1 = a*, c2 = b*.
Color3 xyz_to_lab(const Color3& xyz);

// Hunt effect (FLIP eq.): chroma is scaled by 0.01 L*, because colour differences become less
// visible as luminance drops. L* is kept.
Color3 hunt_adjust(const Color3& lab);

// HyAB distance (Abasi et al. 2020): |dL| + Euclidean distance in (a, b). Better than Euclidean
// Delta E for large differences.
double hyab(const Color3& lab_a, const Color3& lab_b);

}  // namespace ddgi::metrics
