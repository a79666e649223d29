// Default views for scenes that bring no camera, and camera flags.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"

namespace ddgi {

// A camera that sees all of `bounds`: from the +Z side, slightly above, 45 degrees vertical.
Camera fit_camera(const Bounds& bounds);

// The scene's first camera, else one fitted to its bounds.
Camera default_camera(const Scene& scene);

// `values`: px,py,pz, tx,ty,tz [, yfov in degrees] (position and target, +Y up).
Result<Camera> camera_from_values(const std::vector<double>& values, const Camera& base);

}  // namespace ddgi
