// Emitter light sampled per pixel (IrradianceFieldParams::emitter_samples) instead of carried
// by the field: analytically right, and never counted twice.
#include <gtest/gtest.h>

#include <cmath>

#include "gi/irradiance_field.h"
#include "gpu_scene/gpu_scene.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"

namespace ddgi::test {
namespace {

class EmitterSamplingTest : public GpuTest {
 protected:
  // Mean radiance over the image of `scene` seen from its camera, after a warmed-up field.
  glm::vec3 mean_radiance(const Scene& scene, const IrradianceFieldParams& params, View view,
                          uint32_t size = 24) {
    auto gpu = GpuScene::create(context(), scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    if (!gpu.ok()) return glm::vec3(-1.0f);
    auto field = IrradianceField::create(context(), **gpu, params, context().default_backend());
    EXPECT_TRUE(field.ok()) << field.error().message;
    if (!field.ok()) return glm::vec3(-1.0f);
    EXPECT_TRUE((*field)->warm_up(48, DirectMode::kTracedShadows).ok());
    auto renderer = Renderer::create(context(), **gpu, field->get(), context().default_backend());
    EXPECT_TRUE(renderer.ok());
    FrameSettings settings;
    settings.width = settings.height = size;
    settings.camera = scene.cameras[0];
    settings.view = view;
    auto frame = render_updated(**renderer, settings, field->get());
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    if (!frame.ok()) return glm::vec3(-1.0f);
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < frame->radiance.size(); i += 4) {
      sum += glm::dvec3(frame->radiance[i], frame->radiance[i + 1], frame->radiance[i + 2]);
    }
    return glm::vec3(sum / double(frame->radiance.size() / 4));
  }
};

// A 0.1 m square emitter (radiance 100, facing down) 1 m above a floor of albedo 0.5; the
// camera, below the emitter, sees a 2 cm patch of floor under it. The floor reflects
// rho / pi x E with E = L x A / h^2 = 1 (small-source form factor; error below 1% here).
TEST_F(EmitterSamplingTest, SampledEmitterLightMatchesTheFormFactor) {
  Scene scene;
  const int floor = add_material(scene, glm::vec3(0.5f));
  add_quad(scene, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, {-5, 0, -5}, floor);
  const int emitter = add_material(scene, glm::vec3(0.0f), glm::vec3(100.0f), "emitter");
  add_quad(scene, {-0.05f, 1, -0.05f}, {0.05f, 1, -0.05f}, {0.05f, 1, 0.05f}, {-0.05f, 1, 0.05f},
           emitter);  // counter-clockwise seen from below: facing down
  Camera camera;
  camera.position = {0.0f, 0.5f, 0.0f};
  camera.forward = {0.0f, -1.0f, 0.0f};
  camera.up = {0.0f, 0.0f, -1.0f};
  camera.yfov = 0.04f;
  scene.cameras.push_back(camera);
  IrradianceFieldParams p;
  p.origin = {-1.0f, 0.5f, -1.0f};
  p.spacing = {2.0f, 1.0f, 2.0f};
  p.counts = {2, 1, 2};
  p.rays_per_probe = 16;
  p.emitter_samples = 64;
  const glm::vec3 direct = mean_radiance(scene, p, View::kDirect);
  const float expected = 0.5f / 3.14159265f * 1.0f;
  EXPECT_NEAR(direct.x, expected, 0.03f * expected);
  EXPECT_NEAR(direct.y, expected, 0.03f * expected);
}

// A closed white room lit only by a small bright ceiling panel. With sampling on, the image
// matches the path-traced reference (so emitter light is counted once: the field must not also
// carry what probe rays see of the panel). Carried by a coarse field instead, the panel's steep
// near field is interpolated linearly between probes 1 m apart and comes out too bright
// (measured: +74% here); that trade is what the option exists to measure.
TEST_F(EmitterSamplingTest, SampledEmittersMatchThePathTracedReference) {
  Scene scene = make_white_furnace_box(0.5f, 0.0f);  // a closed white room, no emission
  scene.materials.push_back(Material{});
  scene.materials.back().base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  scene.materials.back().emissive = glm::vec3(20.0f);
  const int panel = static_cast<int>(scene.materials.size()) - 1;
  add_quad(scene, {-0.25f, 1.99f, -0.25f}, {0.25f, 1.99f, -0.25f}, {0.25f, 1.99f, 0.25f},
           {-0.25f, 1.99f, 0.25f}, panel);  // a ceiling panel facing down

  auto gpu = GpuScene::create(context(), scene);
  ASSERT_TRUE(gpu.ok());
  auto tracer = PathTracer::create(context(), **gpu, context().default_backend());
  ASSERT_TRUE(tracer.ok());
  PathTraceSettings pt;
  pt.width = pt.height = 24;
  pt.camera = scene.cameras[0];
  pt.jitter = false;
  ASSERT_TRUE((*tracer)->accumulate(pt, 1024).ok());
  auto reference = (*tracer)->read();
  ASSERT_TRUE(reference.ok());
  double sum = 0.0;
  for (size_t i = 0; i < reference->radiance.size(); i += 4) sum += reference->radiance[i];
  const float expected = static_cast<float>(sum / (reference->radiance.size() / 4));

  IrradianceFieldParams p;
  p.origin = {-0.5f, 0.5f, -0.5f};
  p.spacing = {1.0f, 1.0f, 1.0f};
  p.counts = {2, 2, 2};
  p.rays_per_probe = 128;
  const glm::vec3 carried = mean_radiance(scene, p, View::kFull);
  p.emitter_samples = 16;
  const glm::vec3 sampled = mean_radiance(scene, p, View::kFull);
  std::printf("mean radiance: reference %.4f, emitters sampled %.4f, through the field %.4f\n",
              expected, sampled.x, carried.x);
  EXPECT_NEAR(sampled.x, expected, 0.1f * expected);
}

}  // namespace
}  // namespace ddgi::test
