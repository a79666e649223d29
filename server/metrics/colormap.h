// Error-map visualisation: a dark-to-bright colour ramp in the spirit of matplotlib's "magma"
// (black, purple, red-orange, pale yellow), so larger errors are always lighter and the map
// still reads correctly when printed in grey.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace ddgi::metrics {

// t in [0,1] (clamped; NaN maps to 0) -> sRGB-encoded 8-bit colour.
std::array<uint8_t, 3> error_color(float t);

// One RGBA8 pixel (alpha 255) per error value, same order.
std::vector<uint8_t> colorize_errors(std::span<const float> errors);

}  // namespace ddgi::metrics
