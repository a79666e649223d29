#include "tests/gpu/procedural.h"

#include <glm/gtc/matrix_transform.hpp>

namespace ddgi::test {

int add_material(Scene& scene, glm::vec3 albedo, glm::vec3 emissive, const std::string& name) {
  Material m;
  m.name = name;
  m.base_color = glm::vec4(albedo, 1.0f);
  m.emissive = emissive;
  scene.materials.push_back(m);
  return static_cast<int>(scene.materials.size()) - 1;
}

int add_quad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, int material,
             bool with_normals) {
  Primitive prim;
  prim.positions = {a, b, c, d};
  prim.indices = {0, 1, 2, 0, 2, 3};
  if (with_normals) {
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    prim.normals = {n, n, n, n};
  }
  prim.texcoords0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  prim.material = material;
  Mesh mesh;
  mesh.primitives.push_back(prim);
  scene.meshes.push_back(mesh);
  Instance inst;
  inst.mesh = static_cast<int>(scene.meshes.size()) - 1;
  scene.instances.push_back(inst);
  return static_cast<int>(scene.instances.size()) - 1;
}

int add_box(Scene& scene, const glm::mat4& transform, int material) {
  Primitive prim;
  prim.material = material;
  // Six faces, each a quad wound counter-clockwise seen from outside.
  const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int axis = 0; axis < 3; ++axis) {
    for (float side : {-1.0f, 1.0f}) {
      const glm::vec3 n = axes[axis] * side;
      const glm::vec3 u = axes[(axis + 1) % 3];
      const glm::vec3 v = axes[(axis + 2) % 3] * side;
      const uint32_t base = static_cast<uint32_t>(prim.positions.size());
      const glm::vec3 center = n * 0.5f;
      prim.positions.push_back(center - 0.5f * u - 0.5f * v);
      prim.positions.push_back(center + 0.5f * u - 0.5f * v);
      prim.positions.push_back(center + 0.5f * u + 0.5f * v);
      prim.positions.push_back(center - 0.5f * u + 0.5f * v);
      for (int i = 0; i < 4; ++i) prim.normals.push_back(n);
      prim.indices.insert(prim.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  Mesh mesh;
  mesh.primitives.push_back(prim);
  scene.meshes.push_back(mesh);
  Instance inst;
  inst.mesh = static_cast<int>(scene.meshes.size()) - 1;
  inst.transform = transform;
  scene.instances.push_back(inst);
  return static_cast<int>(scene.instances.size()) - 1;
}

Scene make_cornell_box() {
  Scene scene;
  scene.source = "procedural cornell box";
  const int white = add_material(scene, {0.725f, 0.71f, 0.68f}, {}, "white");
  const int red = add_material(scene, {0.63f, 0.065f, 0.05f}, {}, "red");
  const int green = add_material(scene, {0.14f, 0.45f, 0.091f}, {}, "green");
  // Inward-facing walls.
  add_quad(scene, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, white);    // floor
  add_quad(scene, {-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}, white);    // ceiling
  add_quad(scene, {-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}, white);  // back
  add_quad(scene, {-1, 0, 1}, {-1, 0, -1}, {-1, 2, -1}, {-1, 2, 1}, red);    // left
  add_quad(scene, {1, 0, -1}, {1, 0, 1}, {1, 2, 1}, {1, 2, -1}, green);      // right
  glm::mat4 tall = glm::translate(glm::mat4(1.0f), {-0.35f, 0.6f, -0.3f});
  tall = glm::rotate(tall, glm::radians(18.0f), {0, 1, 0});
  add_box(scene, glm::scale(tall, {0.6f, 1.2f, 0.6f}), white);
  glm::mat4 small = glm::translate(glm::mat4(1.0f), {0.35f, 0.3f, 0.35f});
  small = glm::rotate(small, glm::radians(-17.0f), {0, 1, 0});
  add_box(scene, glm::scale(small, {0.6f, 0.6f, 0.6f}), white);
  Light light;
  light.name = "ceiling light";
  light.type = LightType::kPoint;
  light.position = {0.0f, 1.9f, 0.0f};
  light.intensity = 3.0f;
  scene.lights.push_back(light);
  Camera camera;
  camera.position = {0.0f, 1.0f, 3.4f};
  camera.forward = {0.0f, 0.0f, -1.0f};
  camera.up = {0.0f, 1.0f, 0.0f};
  camera.yfov = glm::radians(40.0f);
  scene.cameras.push_back(camera);
  return scene;
}

void scale_scene(Scene& scene, float s) {
  const glm::mat4 scale = glm::scale(glm::mat4(1.0f), glm::vec3(s));
  for (Instance& inst : scene.instances) inst.transform = scale * inst.transform;
  for (Light& light : scene.lights) {
    light.position *= s;
    if (light.type != LightType::kDirectional) light.intensity *= s * s;
    light.range *= s;
    light.radius *= s;
  }
  for (Camera& camera : scene.cameras) {
    camera.position *= s;
    camera.znear *= s;
  }
}

Scene make_white_furnace_box(float albedo, float emission) {
  Scene scene;
  scene.source = "procedural white furnace box";
  const int m = add_material(scene, glm::vec3(albedo), glm::vec3(emission), "furnace");
  add_quad(scene, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, m);
  add_quad(scene, {-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}, m);
  add_quad(scene, {-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}, m);
  add_quad(scene, {1, 0, 1}, {-1, 0, 1}, {-1, 2, 1}, {1, 2, 1}, m);
  add_quad(scene, {-1, 0, 1}, {-1, 0, -1}, {-1, 2, -1}, {-1, 2, 1}, m);
  add_quad(scene, {1, 0, -1}, {1, 0, 1}, {1, 2, 1}, {1, 2, -1}, m);
  Camera camera;
  camera.position = {0.0f, 1.0f, 0.9f};
  camera.forward = {0.0f, 0.0f, -1.0f};
  camera.yfov = glm::radians(60.0f);
  scene.cameras.push_back(camera);
  return scene;
}

Scene make_corridor() {
  Scene scene;
  scene.source = "procedural corridor";
  const int white = add_material(scene, {0.725f, 0.71f, 0.68f}, {}, "white");
  const int red = add_material(scene, {0.63f, 0.065f, 0.05f}, {}, "red");
  const int green = add_material(scene, {0.14f, 0.45f, 0.091f}, {}, "green");
  // Inward-facing.
  add_quad(scene, {-3, 0, 1}, {3, 0, 1}, {3, 0, -1}, {-3, 0, -1}, white);    // floor
  add_quad(scene, {-3, 2, -1}, {3, 2, -1}, {3, 2, 1}, {-3, 2, 1}, white);    // ceiling
  add_quad(scene, {-3, 0, -1}, {3, 0, -1}, {3, 2, -1}, {-3, 2, -1}, red);    // back
  add_quad(scene, {3, 0, 1}, {-3, 0, 1}, {-3, 2, 1}, {3, 2, 1}, green);      // front
  add_quad(scene, {-3, 0, 1}, {-3, 0, -1}, {-3, 2, -1}, {-3, 2, 1}, white);  // left end
  add_quad(scene, {3, 0, -1}, {3, 0, 1}, {3, 2, 1}, {3, 2, -1}, white);      // right end
  for (float x : {-2.0f, 0.0f, 2.0f}) {
    Light light;
    light.type = LightType::kPoint;
    light.position = {x, 1.9f, 0.0f};
    light.intensity = 2.0f;
    scene.lights.push_back(light);
  }
  return scene;
}

}  // namespace ddgi::test
