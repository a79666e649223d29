// The scene's value-type helpers: a look-at camera, bounds, and what lights it.
#include "scene/scene.h"

#include <algorithm>
#include <cmath>

namespace ddgi {

namespace {

// Past this many instanced vertices, exact bounds would take seconds (instancing multiplies
// them); the transformed box of each mesh's bounds is used instead.
constexpr uint64_t kExactBoundsVertexBudget = uint64_t{1} << 26;

Bounds object_bounds(const Mesh& mesh) {
  Bounds bounds;
  for (const Primitive& prim : mesh.primitives) {
    for (const glm::vec3& p : prim.positions) bounds.grow(p);
  }
  return bounds;
}

// The box around `box`'s eight corners after `transform` (empty stays empty).
Bounds transformed_box(const Bounds& box, const glm::mat4& transform) {
  Bounds out;
  if (box.empty()) return out;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                      (corner & 4) ? box.max.z : box.min.z);
    out.grow(glm::vec3(transform * glm::vec4(p, 1.0f)));
  }
  return out;
}

void grow_bounds(Bounds& bounds, const Bounds& other) {
  if (other.empty()) return;
  bounds.grow(other.min);
  bounds.grow(other.max);
}

// Flat: thinner than 1% of its largest side along some axis (a plane, a wall, a floor).
bool is_flat(const Bounds& box) {
  const glm::vec3 e = box.extent();
  const float largest = std::max({e.x, e.y, e.z});
  return largest > 0.0f && std::min({e.x, e.y, e.z}) < 0.01f * largest;
}

// A flat instance reaching this many times further than everything else (on its largest side)
// is a ground plane under the scene rather than part of it.
constexpr float kGroundReach = 4.0f;

}  // namespace

Result<Camera> look_at_camera(glm::vec3 position, glm::vec3 target, glm::vec3 up, float yfov) {
  const glm::vec3 view = target - position;
  const float distance = glm::length(view);
  if (!(distance > 1e-6f) || !std::isfinite(distance)) {
    return invalid_argument("'position' and 'target' must differ (by a finite distance)");
  }
  Camera camera;
  camera.position = position;
  camera.forward = view / distance;
  const glm::vec3 orthogonal_up = up - glm::dot(up, camera.forward) * camera.forward;
  if (!(glm::length(orthogonal_up) > 1e-4f)) {
    return invalid_argument("'up' must not be parallel to the view direction");
  }
  camera.up = glm::normalize(orthogonal_up);
  camera.yfov = yfov;
  return camera;
}

Bounds Scene::world_bounds() const {
  uint64_t instanced_vertices = 0;
  for (const Instance& instance : instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= meshes.size()) continue;
    for (const Primitive& prim : meshes[static_cast<size_t>(instance.mesh)].primitives) {
      instanced_vertices += prim.positions.size();
    }
  }
  const bool exact = instanced_vertices <= kExactBoundsVertexBudget;
  std::vector<Bounds> mesh_bounds;
  if (!exact) {
    for (const Mesh& mesh : meshes) mesh_bounds.push_back(object_bounds(mesh));
  }
  Bounds bounds;
  for (const Instance& instance : instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= meshes.size()) continue;
    const size_t m = static_cast<size_t>(instance.mesh);
    if (exact) {
      for (const Primitive& prim : meshes[m].primitives) {
        for (const glm::vec3& p : prim.positions) {
          bounds.grow(glm::vec3(instance.transform * glm::vec4(p, 1.0f)));
        }
      }
    } else if (!mesh_bounds[m].empty()) {
      grow_bounds(bounds, transformed_box(mesh_bounds[m], instance.transform));
    }
  }
  return bounds;
}

std::optional<Bounds> Scene::bounds_without_ground() const {
  std::vector<Bounds> mesh_boxes;  // once per mesh: instancing repeats meshes many times
  for (const Mesh& mesh : meshes) mesh_boxes.push_back(object_bounds(mesh));
  std::vector<Bounds> boxes;
  for (const Instance& instance : instances) {
    if (instance.mesh < 0 || static_cast<size_t>(instance.mesh) >= meshes.size()) continue;
    boxes.push_back(
        transformed_box(mesh_boxes[static_cast<size_t>(instance.mesh)], instance.transform));
  }
  Bounds solid;  // everything but the flat instances
  for (const Bounds& box : boxes) {
    if (!is_flat(box)) grow_bounds(solid, box);
  }
  const glm::vec3 solid_extent = solid.extent();
  const float reach = std::max({solid_extent.x, solid_extent.y, solid_extent.z});
  if (!(reach > 0.0f)) return std::nullopt;
  Bounds out = solid;
  bool ground = false;
  for (const Bounds& box : boxes) {
    if (!is_flat(box)) continue;
    const glm::vec3 e = box.extent();
    if (std::max({e.x, e.y, e.z}) > kGroundReach * reach) {
      ground = true;
    } else {
      grow_bounds(out, box);  // a wall, a floor of the scene's size
    }
  }
  return ground ? std::optional<Bounds>(out) : std::nullopt;
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
  return environment_lit || has_emissive_surfaces();
}

bool Scene::has_emissive_surfaces() const {
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
