// The Scene stores floats; a double from a file that is finite but beyond float range would
// become infinity on conversion, so numeric checks use this instead of std::isfinite.
#pragma once

#include <cmath>
#include <limits>

namespace ddgi {

inline bool finite_as_float(double value) {
  return std::isfinite(value) && std::fabs(value) <= std::numeric_limits<float>::max();
}

}  // namespace ddgi
