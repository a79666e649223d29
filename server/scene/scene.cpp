#include "scene/scene.h"

namespace ddgi {

Bounds Scene::world_bounds() const {
  Bounds bounds;
  for (const Instance& instance : instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= meshes.size()) continue;
    for (const Primitive& prim : meshes[static_cast<size_t>(instance.mesh)].primitives) {
      for (const glm::vec3& p : prim.positions) {
        bounds.grow(glm::vec3(instance.transform * glm::vec4(p, 1.0f)));
      }
    }
  }
  return bounds;
}

bool Scene::has_any_light() const {
  for (const Light& light : lights) {
    if (light.intensity > 0.0f && glm::any(glm::greaterThan(light.color, glm::vec3(0.0f)))) {
      return true;
    }
  }
  const bool environment_lit = environment.intensity > 0.0f &&
                               (environment.image.has_value() ||
                                glm::any(glm::greaterThan(environment.color, glm::vec3(0.0f))));
  if (environment_lit) return true;
  // Only emissive materials that some placed primitive uses give light.
  for (const Instance& instance : instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= meshes.size()) continue;
    for (const Primitive& prim : meshes[static_cast<size_t>(instance.mesh)].primitives) {
      if (prim.material < 0 || static_cast<size_t>(prim.material) >= materials.size()) continue;
      if (glm::any(glm::greaterThan(materials[static_cast<size_t>(prim.material)].emissive,
                                    glm::vec3(0.0f)))) {
        return true;
      }
    }
  }
  return false;
}

}  // namespace ddgi
