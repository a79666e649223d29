#include "tests/gpu/white_box.h"

#include <gtest/gtest.h>

#include "tests/gpu/shadow_test_support.h"

namespace ddgi::test {

Scene load_white_box(float albedo, float emission) {
  Scene scene = load_repo_scene("white_box.gltf");
  // Every surface must get the new values: a primitive without a material would keep the
  // default white, non-emissive one and break the furnace silently.
  EXPECT_EQ(scene.materials.size(), 1u) << "white_box.gltf should have one material";
  for (const Mesh& mesh : scene.meshes) {
    for (const Primitive& primitive : mesh.primitives) EXPECT_EQ(primitive.material, 0);
  }
  EXPECT_TRUE(scene.lights.empty()) << "the furnace has no punctual light";
  for (Material& material : scene.materials) {
    material.base_color = glm::vec4(glm::vec3(albedo), 1.0f);
    material.emissive = glm::vec3(emission);
    material.base_color_texture = -1;
    material.emissive_texture = -1;
  }
  return scene;
}

IrradianceFieldParams white_box_grid() {
  IrradianceFieldParams params;
  params.origin = {-0.5f, 0.5f, -0.5f};
  params.spacing = glm::vec3(1.0f);
  params.counts = {2, 2, 2};
  params.rays_per_probe = 64;
  return params;
}

}  // namespace ddgi::test
