// Changes to glTF materials requested by a sidecar (docs/sidecar-format.md, `materials`).
// They apply while materials are converted, where the glTF's emissive factor and strength are
// still separate.
#pragma once

#include <map>
#include <optional>
#include <string>

#include <glm/glm.hpp>

namespace ddgi {

struct MaterialOverride {
  std::optional<glm::vec4> base_color;     // replaces baseColorFactor
  std::optional<glm::vec3> emissive;       // replaces emissiveFactor
  std::optional<float> emissive_strength;  // replaces KHR_materials_emissive_strength
  std::optional<float> transmission;       // replaces KHR_materials_transmission's factor
  std::optional<bool> double_sided;
};

// By material name; every material with that name is changed.
using MaterialOverrides = std::map<std::string, MaterialOverride>;

}  // namespace ddgi
