// glTF meshes to triangle lists (glTF 2.0 section 3.7.2): strips and fans become lists,
// non-indexed primitives get generated indices, points and lines are skipped with a warning.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "core/result.h"
#include "scene/scene.h"

namespace ddgi {

// What the rest of the scene may still use; decremented as meshes are converted.
struct GeometryBudget {
  uint64_t vertices_left = 0;
  uint64_t triangles_left = 0;
  uint64_t primitives_left = 0;
  uint64_t max_triangles = 0;   // for messages
  uint64_t max_primitives = 0;  // for messages
};

// Mesh `index` (already validated by validate_gltf). Primitives with no triangles are left
// out with a warning, so the result may have none.
Result<Mesh> convert_mesh(const tinygltf::Model& model, int index, GeometryBudget* budget,
                          std::vector<std::string>* warnings);

}  // namespace ddgi
