// glTF materials to Scene materials (metallic-roughness base colour, emission with
// KHR_materials_emissive_strength, alpha, KHR_materials_transmission), and the textures they
// use decoded to RGBA8. Images no material colour uses are never decoded.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "core/result.h"
#include "scene/material_override.h"
#include "scene/scene.h"
#include "scene/scene_limits.h"

namespace ddgi {

// Fills scene->materials (same indices as the file's) and scene->textures. The model must
// already be validated; its images must hold encoded bytes (see parse_gltf).
Status convert_materials(const tinygltf::Model& model, const MaterialOverrides& overrides,
                         const SceneLimits& limits, Scene* scene);

}  // namespace ddgi
