// The node hierarchy of the scene to render, flattened to world transforms. glTF requires the
// nodes to form a forest; a file whose nodes do not (a node with two parents, a cycle) is
// refused rather than walked, since walking it could place a mesh twice or never end.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>
#include <glm/glm.hpp>

#include "core/result.h"
#include "scene/scene_limits.h"

namespace ddgi {

struct PlacedNode {
  int node = -1;
  glm::mat4 world{1.0f};  // object to world
};

// The nodes of `scene` (else scene 0, else every root node, with a warning), parents before
// children, children in file order. Node references must already be validated.
Result<std::vector<PlacedNode>> place_nodes(const tinygltf::Model& model, const SceneLimits& limits,
                                            std::vector<std::string>* warnings);

}  // namespace ddgi
