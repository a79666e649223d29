// A parsed and validated glTF model to the CPU Scene: the default scene's nodes become
// instances (meshes converted once each, in first-use order), KHR_lights_punctual lights and
// perspective cameras placed by their nodes' world transforms, and materials with textures.
#pragma once

#include <tiny_gltf.h>

#include "core/result.h"
#include "scene/material_override.h"
#include "scene/scene.h"
#include "scene/scene_limits.h"

namespace ddgi {

Result<Scene> convert_gltf(const tinygltf::Model& model, const MaterialOverrides& overrides,
                           const SceneLimits& limits);

}  // namespace ddgi
