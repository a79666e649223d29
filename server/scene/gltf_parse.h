// The boundary to tinygltf: it parses JSON and decodes data URIs, but it only sees input that
// passed our container and nesting checks, reads files only through our sandbox, keeps images
// encoded (after checking their headers), and its exceptions stop here.
#pragma once

#include <cstdint>
#include <span>

#include <tiny_gltf.h>

#include "core/result.h"
#include "scene/scene_files.h"
#include "scene/scene_limits.h"

namespace ddgi {

// `bytes` is a .gltf JSON text or a whole .glb (told apart by the GLB magic). URIs resolve in
// `folder`; a default SceneFolder refuses all of them. On success every image holds its
// encoded PNG/JPEG bytes in Image::image with as_is = true and width/height from its header.
// Errors carry no file name; the caller adds it.
Result<tinygltf::Model> parse_gltf(std::span<const uint8_t> bytes, const SceneFolder& folder,
                                   const SceneLimits& limits);

}  // namespace ddgi
