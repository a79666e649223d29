// Structural checks of a parsed glTF before anything is converted: every index field points
// at something that exists, every buffer view lies inside its buffer, every accessor inside
// its buffer view, transforms are finite and well formed. tinygltf checks few of these.
#pragma once

#include <tiny_gltf.h>

#include "core/result.h"

namespace ddgi {

// `binary`: the model came from a GLB (only buffer 0 may then omit its uri).
Status validate_gltf(const tinygltf::Model& model, bool binary);

}  // namespace ddgi
