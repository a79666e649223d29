#include "scene/gltf_convert.h"

#include <cmath>
#include <vector>

#include "scene/gltf_geometry.h"
#include "scene/gltf_materials.h"
#include "scene/gltf_nodes.h"
#include "scene/gltf_values.h"

namespace ddgi {
namespace {

constexpr int kNotConverted = -1;
constexpr int kNoTriangles = -2;

// Unit vector of a transformed axis, or nullopt when the transform collapses it.
std::optional<glm::vec3> transformed_direction(const glm::mat4& world, const glm::vec3& axis) {
  const glm::vec3 v = glm::mat3(world) * axis;
  const float length = glm::length(v);
  if (!(length > 1e-20f) || !std::isfinite(length)) return std::nullopt;
  return v / length;
}

std::optional<Light> convert_light(const tinygltf::Light& light, const PlacedNode& placed,
                                   std::vector<std::string>* warnings) {
  Light out;
  out.name = light.name;
  out.type = light.type == "spot"          ? LightType::kSpot
             : light.type == "directional" ? LightType::kDirectional
                                           : LightType::kPoint;
  if (light.color.size() == 3) {
    out.color = glm::vec3(light.color[0], light.color[1], light.color[2]);
  }
  out.intensity = static_cast<float>(light.intensity);
  out.range = static_cast<float>(light.range);
  out.inner_cone_angle = static_cast<float>(light.spot.innerConeAngle);
  out.outer_cone_angle = static_cast<float>(light.spot.outerConeAngle);
  out.position = glm::vec3(placed.world[3]);
  // KHR_lights_punctual: lights shine along the node's local -Z.
  const std::optional<glm::vec3> direction =
      transformed_direction(placed.world, glm::vec3(0.0f, 0.0f, -1.0f));
  if (!direction) {
    warnings->push_back("nodes[" + std::to_string(placed.node) +
                        "]: the light's transform has no direction (zero scale); light skipped");
    return std::nullopt;
  }
  out.direction = *direction;
  return out;
}

std::optional<Camera> convert_camera(const tinygltf::Camera& camera, const tinygltf::Node& node,
                                     const PlacedNode& placed, std::vector<std::string>* warnings) {
  const std::string where = "nodes[" + std::to_string(placed.node) + "]";
  if (camera.type != "perspective") {
    warnings->push_back(where + ": " + camera.type + " camera skipped (only perspective)");
    return std::nullopt;
  }
  const std::optional<glm::vec3> forward =
      transformed_direction(placed.world, glm::vec3(0.0f, 0.0f, -1.0f));
  const std::optional<glm::vec3> up_axis =
      transformed_direction(placed.world, glm::vec3(0.0f, 1.0f, 0.0f));
  std::optional<glm::vec3> up;
  if (forward && up_axis) {
    // Shear or non-uniform scale can tilt +Y off the view plane: Gram-Schmidt.
    const glm::vec3 orthogonal = *up_axis - glm::dot(*up_axis, *forward) * *forward;
    const float length = glm::length(orthogonal);
    if (length > 1e-6f) up = orthogonal / length;
  }
  if (!forward || !up) {
    warnings->push_back(where + ": the camera's transform is degenerate; camera skipped");
    return std::nullopt;
  }
  Camera out;
  out.name = !camera.name.empty() ? camera.name : node.name;
  out.position = glm::vec3(placed.world[3]);
  out.forward = *forward;
  out.up = *up;
  out.yfov = static_cast<float>(camera.perspective.yfov);
  out.znear = static_cast<float>(camera.perspective.znear);
  return out;
}

int node_light(const tinygltf::Node& node) {
  // validate_gltf has checked the index; here it is only read.
  Result<std::optional<int>> light =
      optional_int(find_extension(node.extensions, "KHR_lights_punctual"), "light", "");
  return light.ok() && light->has_value() ? **light : -1;
}

}  // namespace

Result<Scene> convert_gltf(const tinygltf::Model& model, const MaterialOverrides& overrides,
                           const SceneLimits& limits) {
  Scene scene;
  DDGI_ASSIGN_OR_RETURN(const std::vector<PlacedNode> placed,
                        place_nodes(model, limits, &scene.warnings));

  GeometryBudget budget;
  budget.vertices_left = limits.max_vertices;
  budget.triangles_left = limits.max_triangles;
  budget.primitives_left = limits.max_primitives;
  budget.max_triangles = limits.max_triangles;
  budget.max_primitives = limits.max_primitives;
  std::vector<int> scene_mesh(model.meshes.size(), kNotConverted);
  for (const PlacedNode& p : placed) {
    const tinygltf::Node& node = model.nodes[static_cast<size_t>(p.node)];
    if (node.mesh >= 0) {
      int& mesh = scene_mesh[static_cast<size_t>(node.mesh)];
      if (mesh == kNotConverted) {
        DDGI_ASSIGN_OR_RETURN(Mesh converted,
                              convert_mesh(model, node.mesh, &budget, &scene.warnings));
        if (converted.primitives.empty()) {
          scene.warnings.push_back("meshes[" + std::to_string(node.mesh) +
                                   "] has no triangles; the nodes placing it are skipped");
          mesh = kNoTriangles;
        } else {
          mesh = static_cast<int>(scene.meshes.size());
          scene.meshes.push_back(std::move(converted));
        }
      }
      if (mesh >= 0) {
        if (scene.instances.size() >= limits.max_instances) {
          return resource_exhausted("the scene places more than the limit of " +
                                    std::to_string(limits.max_instances) + " mesh instances");
        }
        scene.instances.push_back(Instance{node.name, p.node, mesh, p.world});
      }
    }
    const int light = node_light(node);
    if (light >= 0) {
      std::optional<Light> converted =
          convert_light(model.lights[static_cast<size_t>(light)], p, &scene.warnings);
      if (converted) {
        if (scene.lights.size() >= limits.max_lights) {
          return resource_exhausted("the scene has more than the limit of " +
                                    std::to_string(limits.max_lights) + " lights");
        }
        scene.lights.push_back(std::move(*converted));
      }
    }
    if (node.camera >= 0) {
      std::optional<Camera> converted =
          convert_camera(model.cameras[static_cast<size_t>(node.camera)], node, p, &scene.warnings);
      if (converted) scene.cameras.push_back(std::move(*converted));
    }
  }
  DDGI_TRY(convert_materials(model, overrides, limits, &scene));
  if (!model.animations.empty()) scene.warnings.push_back("animations are ignored");
  if (!model.skins.empty())
    scene.warnings.push_back("skins are ignored (meshes stay in bind pose)");
  return scene;
}

}  // namespace ddgi
