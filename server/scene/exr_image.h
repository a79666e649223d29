// Equirectangular environment maps from OpenEXR files (RGB or RGBA, half or float, any
// compression OpenEXR reads), for the sidecar's `environment.image`.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"
#include "scene/scene_limits.h"

namespace ddgi {

// Linear RGB floats, row 0 at the top. Checks the file size and the image dimensions before
// reading pixels. Negative and non-finite pixels become 0, with a warning.
Result<EnvironmentImage> load_exr_environment(const std::filesystem::path& path,
                                              const SceneLimits& limits,
                                              std::vector<std::string>* warnings);

}  // namespace ddgi
