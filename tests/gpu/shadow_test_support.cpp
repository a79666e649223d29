#include "tests/gpu/shadow_test_support.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scene/gltf_loader.h"

namespace ddgi::test {

Scene load_repo_scene(const std::string& name) {
  auto scene = load_scene(std::string(DDGI_SOURCE_DIR) + "/scenes/" + name);
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  return scene.ok() ? std::move(scene).value() : Scene{};
}

ShadowSetup make_shadow_setup(vk::Context& context, const Scene& scene,
                              const ShadowFieldParams& params, vk::TraceBackend backend) {
  ShadowSetup s;
  auto gpu = GpuScene::create(context, scene);
  EXPECT_TRUE(gpu.ok()) << gpu.error().message;
  if (!gpu.ok()) return s;
  s.scene = std::move(gpu).value();
  auto field = ShadowField::create(context, *s.scene, params, backend);
  EXPECT_TRUE(field.ok()) << field.error().message;
  if (field.ok()) s.field = std::move(field).value();
  return s;
}

ShadowFieldParams box_on_floor_grid() {
  ShadowFieldParams p;
  p.origin = {-2.75f, 0.25f, -2.75f};
  p.spacing = {0.5f, 0.5f, 0.5f};
  p.counts = {13, 3, 12};
  return p;
}

std::vector<ShadowFieldQuery> box_floor_points(float x0, float x1, float z0, float z1, float step) {
  std::vector<ShadowFieldQuery> points;
  for (float x = x0; x <= x1 + 1e-4f; x += step) {
    for (float z = z0; z <= z1 + 1e-4f; z += step) {
      if (std::abs(x) <= 0.55f && std::abs(z) <= 0.55f) continue;
      ShadowFieldQuery q;
      q.position = {x, 0.0f, z};
      q.normal = {0.0f, 1.0f, 0.0f};
      q.to_viewer = glm::normalize(glm::vec3(0.3f, 1.0f, 0.3f));
      points.push_back(q);
    }
  }
  return points;
}

float mean_abs_visibility_error(const std::vector<ShadowFieldAnswer>& answers, uint32_t light) {
  double sum = 0.0;
  for (const ShadowFieldAnswer& a : answers) {
    sum += std::abs(a.field_visibility[light] - a.traced_visibility[light]);
  }
  return answers.empty() ? 0.0f : static_cast<float>(sum / answers.size());
}

bool all_finite(const std::vector<ShadowFieldAnswer>& answers) {
  for (const ShadowFieldAnswer& a : answers) {
    for (uint32_t l = 0; l < gpu::kShadowMaxLights; ++l) {
      if (!std::isfinite(a.field_visibility[l]) || !std::isfinite(a.traced_visibility[l])) {
        return false;
      }
    }
    if (!std::isfinite(a.field_ao) || !std::isfinite(a.traced_ao) || !std::isfinite(a.weight_sum)) {
      return false;
    }
  }
  return true;
}

}  // namespace ddgi::test
