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
// `folder`; a default SceneFolder refuses all of them, and everything read through URIs adds
// up against limits.max_file_bytes. On success every image has as_is = true, width/height
// from its checked header, and its encoded PNG/JPEG bytes available through encoded_image().
// Errors carry no file name; the caller adds it.
Result<tinygltf::Model> parse_gltf(std::span<const uint8_t> bytes, const SceneFolder& folder,
                                   const SceneLimits& limits);

// The encoded bytes of an image of a model parse_gltf returned: Image::image, or for an image
// stored in a buffer view, that view's bytes.
std::span<const uint8_t> encoded_image(const tinygltf::Model& model, const tinygltf::Image& image);

}  // namespace ddgi
