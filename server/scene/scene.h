// The CPU-side scene: what the glTF loader and the sidecar produce, what the GPU scene
// uploads. Everything is in world units of the file (metres by glTF convention), linear
// colours, radiometric light units (see docs/scenes.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"

namespace ddgi {

struct Texture {
  std::string name;
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgba8;  // width*height*4 bytes, rows top to bottom
  bool srgb = true;            // base colour and emissive are sRGB-encoded; data maps are not
};

enum class AlphaMode : uint32_t { kOpaque = 0, kMask = 1, kBlend = 2 };

struct Material {
  std::string name;
  glm::vec4 base_color{1.0f};   // linear RGBA factor
  int base_color_texture = -1;  // index into Scene::textures, -1 when none
  int base_color_texcoord = 0;  // which TEXCOORD_n set (0 or 1)
  glm::vec3 emissive{0.0f};     // linear factor, already multiplied by emissive_strength
  int emissive_texture = -1;
  int emissive_texcoord = 0;
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;
  // KHR_materials_transmission, treated as thin glass: rays pass through, tinted by
  // transmission * base colour. 0 means opaque.
  float transmission = 0.0f;
  bool double_sided = false;
};

// One glTF mesh primitive (triangles only), in the mesh's object space.
struct Primitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;     // empty when the file has none: shading uses face normals
  std::vector<glm::vec2> texcoords0;  // empty when absent
  std::vector<glm::vec2> texcoords1;  // empty when absent
  std::vector<uint32_t> indices;      // always filled: generated 0..n-1 for non-indexed
  int material = -1;                  // -1: the default material (white, opaque)
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
};

// One placed mesh: a glTF node that references a mesh, with its world transform.
struct Instance {
  std::string name;  // the node's name (may be empty)
  int node = -1;     // glTF node index, for lookups by the API
  int mesh = -1;
  glm::mat4 transform{1.0f};  // object to world
};

enum class LightType : uint32_t { kPoint = 0, kSpot = 1, kDirectional = 2 };

struct Light {
  std::string name;
  LightType type = LightType::kPoint;
  glm::vec3 color{1.0f};  // linear
  // Point/spot: radiant intensity in W/sr (glTF's candela taken radiometrically).
  // Directional: irradiance in W/m^2 (glTF's lux taken radiometrically).
  float intensity = 1.0f;
  float range = 0.0f;  // 0: infinite (glTF: undefined)
  float inner_cone_angle = 0.0f;
  float outer_cone_angle = 0.7853982f;  // pi/4, the glTF default
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // the direction light travels (glTF -Z of the node)
  float radius = 0.0f;                     // > 0: a spherical light for soft shadows (sidecar only)
};

// The vertical fields of view a camera may have: (0, kMaxCameraYfovDegrees]. The one declaration
// that every boundary (RPC, sidecar, --camera) and the renderer check against.
inline constexpr float kMaxCameraYfovDegrees = 179.0f;
// Degrees to the radians Camera::yfov holds. Every boundary converts with this one function, so
// the largest accepted degree value lands exactly on kMaxCameraYfovRadians, never past it.
constexpr float camera_yfov_radians(float degrees) {
  return degrees * (3.14159265358979f / 180.0f);
}
inline constexpr float kMaxCameraYfovRadians = camera_yfov_radians(kMaxCameraYfovDegrees);
// Whether `radians` is an allowed Camera::yfov (false for NaN).
constexpr bool camera_yfov_in_range(float radians) {
  return radians > 0.0f && radians <= kMaxCameraYfovRadians;
}

struct Camera {
  std::string name;
  glm::vec3 position{0.0f, 0.0f, 5.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // unit
  glm::vec3 up{0.0f, 1.0f, 0.0f};        // unit, orthogonal to forward
  float yfov = 0.8f;                     // radians
  float znear = 1e-3f;                   // rays start here (scene units)
};

// A camera at `position` looking at `target`, `up` (any length) made orthogonal to the view;
// fails, saying why, when the two points coincide or `up` is parallel to the view.
Result<Camera> look_at_camera(glm::vec3 position, glm::vec3 target, glm::vec3 up, float yfov);

struct EnvironmentImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> rgb;  // width*height*3, linear, row 0 = top (direction +Y)
};

// Light from every ray that misses the scene.
struct Environment {
  glm::vec3 color{0.0f};                  // constant radiance when there is no image
  std::optional<EnvironmentImage> image;  // equirectangular, multiplied by `intensity`
  float intensity = 1.0f;
  float rotation_y = 0.0f;  // radians about +Y applied to the lookup direction
};

// Where a probe grid lies: the field's grid and static volumes (gi/field_params.h), and what a
// scene or its sidecar asks for (probe_grid, probe_volumes). One declaration for both layers.
struct GridPlacement {
  glm::vec3 origin{0.0f};  // position of probe (0,0,0)
  glm::vec3 spacing{1.0f};
  glm::ivec3 counts{1};
  bool operator==(const GridPlacement&) const = default;
};
// Static volumes a scene may place: an irradiance field holds 8 volumes (kMaxFieldVolumes), one
// of them its own grid.
inline constexpr size_t kMaxSceneProbeVolumes = 7;

struct Bounds {
  glm::vec3 min{1e30f};
  glm::vec3 max{-1e30f};
  bool empty() const { return min.x > max.x; }
  void grow(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  glm::vec3 extent() const { return empty() ? glm::vec3(0.0f) : max - min; }
  glm::vec3 center() const { return empty() ? glm::vec3(0.0f) : 0.5f * (min + max); }
};

struct Scene {
  std::string source;  // the file it came from, for messages
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;
  std::vector<Light> lights;
  std::vector<Camera> cameras;  // cameras[0] is the default view when present
  Environment environment;
  std::optional<GridPlacement> probe_grid;
  // Static volumes of the irradiance field beside its grid (sidecar `probe_volumes`; the field's
  // static_volumes parameter), e.g. a finer grid in one room.
  std::vector<GridPlacement> probe_volumes;
  std::vector<std::string> warnings;  // non-fatal findings, e.g. "no light"

  // World-space bounds of every instance's vertices. Exact up to 64 M instanced vertices;
  // beyond that (heavy instancing), the union of each instance's transformed mesh box, which
  // may be slightly larger.
  Bounds world_bounds() const;
  // The scene's bounds without its ground planes: flat instances reaching more than 4x further
  // than everything that is not flat (a 157 m plane under a 2 m cube); nothing when there is no
  // such plane (then they are world_bounds()). The default probe grid uses it
  // (default_field_params).
  std::optional<Bounds> bounds_without_ground() const;
  // True when something emits light: a light, an emissive material in use, or the environment.
  bool has_any_light() const;
  // True when an emissive material is in use by a placed primitive (area light the probes and
  // the emitter sampling see).
  bool has_emissive_surfaces() const;
};

}  // namespace ddgi
