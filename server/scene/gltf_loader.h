// Loading scenes: glTF 2.0 (.gltf with external or data-URI buffers, .glb) plus the optional
// sidecar (docs/sidecar-format.md). Every input is treated as hostile: errors are values that
// name the file and the problem, and limits bound memory and time (scene_limits.h).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "core/result.h"
#include "scene/scene.h"
#include "scene/scene_limits.h"

namespace ddgi {

// `path`: a .gltf, a .glb, or a .ddgi.json sidecar naming its scene. For a glTF, the sidecar
// beside it (name.ddgi.json) is applied when present. The glTF may only reference files in
// its own folder.
Result<Scene> load_scene(const std::string& path, const SceneLimits& limits = {});

// An uploaded .glb held in memory: it may reference no external file at all. `name` is used
// in messages and as Scene::source.
Result<Scene> load_glb_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                                   const SceneLimits& limits = {});

// A .gltf JSON text held in memory: only data: URIs are allowed.
Result<Scene> load_gltf_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                                    const SceneLimits& limits = {});

}  // namespace ddgi
