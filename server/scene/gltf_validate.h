// Structural checks of a parsed glTF before anything is converted: every index field points
// at something that exists, every buffer view lies inside its buffer, every accessor inside
// its buffer view, transforms are finite and well formed. tinygltf checks few of these.
#pragma once

#include <tiny_gltf.h>

#include "core/result.h"

namespace ddgi {

Status validate_gltf(const tinygltf::Model& model);

}  // namespace ddgi
