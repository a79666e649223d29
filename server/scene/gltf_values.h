// Typed reads of glTF extension objects, which tinygltf keeps as untyped Value trees.
// Absent members are nullopt; present members of the wrong type are errors.
#pragma once

#include <optional>
#include <string>

#include <tiny_gltf.h>

#include "core/result.h"

namespace ddgi {

// The extension object `name`, or nullptr when absent (or not an object).
const tinygltf::Value* find_extension(const tinygltf::ExtensionMap& extensions,
                                      const std::string& name);

// `where` names the object in messages, e.g. "materials[2].extensions.KHR_materials_...".
Result<std::optional<double>> optional_number(const tinygltf::Value* object, const std::string& key,
                                              const std::string& where);
Result<std::optional<int>> optional_int(const tinygltf::Value* object, const std::string& key,
                                        const std::string& where);

}  // namespace ddgi
