// Emitter light sampled per pixel (IrradianceFieldParams::emitter_samples) instead of carried
// by the field: analytically right, and never counted twice.
#include <gtest/gtest.h>
#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gi/irradiance_field.h"
#include "gpu_scene/gpu_scene.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"

namespace ddgi::test {
namespace {

// A camera `height` above floor point `at`, looking straight down; image columns run along +x
// and rows along +z.
Camera camera_looking_down(glm::vec3 at, float height, float yfov) {
  Camera camera;
  camera.position = at + glm::vec3(0.0f, height, 0.0f);
  camera.forward = {0.0f, -1.0f, 0.0f};
  camera.up = {0.0f, 0.0f, -1.0f};
  camera.yfov = yfov;
  return camera;
}

// Four probes over an open floor: the direct view these tests read does not depend on them.
IrradianceFieldParams small_open_field(uint32_t emitter_samples) {
  IrradianceFieldParams p;
  p.origin = {-1.0f, 0.5f, -1.0f};
  p.spacing = {2.0f, 1.0f, 2.0f};
  p.counts = {2, 1, 2};
  p.rays_per_probe = 16;
  p.emitter_samples = emitter_samples;
  return p;
}

class EmitterSamplingTest : public GpuTest {
 protected:
  // The frame of `scene` seen from its camera (RGBA float per pixel), after a warmed-up field.
  std::vector<float> render_view(const Scene& scene, const IrradianceFieldParams& params, View view,
                                 uint32_t size) {
    auto gpu = GpuScene::create(context(), scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    if (!gpu.ok()) return {};
    auto field = IrradianceField::create(context(), **gpu, params, context().default_backend());
    EXPECT_TRUE(field.ok()) << field.error().message;
    if (!field.ok()) return {};
    EXPECT_TRUE((*field)->warm_up(48, DirectMode::kTracedShadows).ok());
    auto renderer = Renderer::create(context(), **gpu, field->get(), context().default_backend());
    EXPECT_TRUE(renderer.ok());
    if (!renderer.ok()) return {};
    FrameSettings settings;
    settings.width = settings.height = size;
    settings.camera = scene.cameras[0];
    settings.view = view;
    auto frame = render_updated(**renderer, settings, field->get());
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    if (!frame.ok()) return {};
    return frame->radiance;
  }

  // Mean radiance over the image of `scene` seen from its camera, after a warmed-up field.
  glm::vec3 mean_radiance(const Scene& scene, const IrradianceFieldParams& params, View view,
                          uint32_t size = 24) {
    const std::vector<float> radiance = render_view(scene, params, view, size);
    if (radiance.empty()) return glm::vec3(-1.0f);
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < radiance.size(); i += 4) {
      sum += glm::dvec3(radiance[i], radiance[i + 1], radiance[i + 2]);
    }
    return glm::vec3(sum / double(radiance.size() / 4));
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
  scene.cameras.push_back(camera_looking_down({0.0f, 0.0f, 0.0f}, 0.5f, 0.04f));
  const glm::vec3 direct =
      mean_radiance(scene, small_open_field(/*emitter_samples=*/64), View::kDirect);
  const float expected = 0.5f / 3.14159265f * 1.0f;
  EXPECT_NEAR(direct.x, expected, 0.03f * expected);
  EXPECT_NEAR(direct.y, expected, 0.03f * expected);
}

// Irradiance at `p` (normal `n`) from a uniform Lambertian polygon of radiance `radiance` that
// lies wholly above p's horizon (Lambert's polygon formula: L/2 x the sum over edges of the edge's
// angle seen from p times the cosine between n and the normal of the plane through p and it).
double polygon_irradiance(const std::vector<glm::dvec3>& polygon, glm::dvec3 p, glm::dvec3 n,
                          double radiance) {
  double sum = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3 a = glm::normalize(polygon[i] - p);
    const glm::dvec3 b = glm::normalize(polygon[(i + 1) % polygon.size()] - p);
    const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += angle * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return 0.5 * radiance * std::abs(sum);
}

// The near field of an emitter: a triangular wall emitter (radiance 10, 0.2 m wide and high)
// standing on a floor of albedo 0.5, and the camera looking straight down at the 2 cm of floor
// 1-3 cm in front of it, where the emitter fills much of the sky. One sample per pixel, each
// pixel against the analytic value at its centre. Sampled by solid angle, a sample is at most
// radiance x cos x solid angle, so no pixel is far off; sampled by area, the 1 / distance^2 of
// points near the emitter's foot makes a few pixels many times too bright and most too dark.
// (One triangle: emitters are picked by area x luminance, so the two halves of a quad, which
// subtend very different solid angles here, would add a variance that this test is not about.)
TEST_F(EmitterSamplingTest, OneSamplePerPixelMatchesTheNearFieldOfAnEmitter) {
  Scene scene;
  const int floor = add_material(scene, glm::vec3(0.5f));
  add_quad(scene, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, {-5, 0, -5}, floor);
  const float kRadiance = 10.0f;
  const int emitter = add_material(scene, glm::vec3(0.0f), glm::vec3(kRadiance), "emitter");
  const std::vector<glm::dvec3> triangle = {{0, 0, 0.1}, {0, 0, -0.1}, {0, 0.2, 0}};  // facing +x
  add_quad(scene, triangle[0], triangle[1], triangle[2], triangle[2], emitter);       // half empty
  const glm::dvec3 centre(0.02, 0.0, 0.0);
  const double height = 0.5, yfov = 0.04;
  scene.cameras.push_back(camera_looking_down(glm::vec3(centre), float(height), float(yfov)));
  const uint32_t size = 32;
  const std::vector<float> frame =
      render_view(scene, small_open_field(/*emitter_samples=*/1), View::kDirect, size);
  ASSERT_EQ(frame.size(), size_t(size) * size * 4);

  // Pixel centres lie on a uniform grid of the floor square the camera sees.
  const double side = 2.0 * height * std::tan(0.5 * yfov);
  double expected_sum = 0.0, frame_sum = 0.0, squared = 0.0, largest = 0.0;
  for (uint32_t j = 0; j < size; ++j) {
    for (uint32_t i = 0; i < size; ++i) {
      const glm::dvec3 point = centre + glm::dvec3(((i + 0.5) / size - 0.5) * side, 0.0,
                                                   ((j + 0.5) / size - 0.5) * side);
      const double expected =
          0.5 / glm::pi<double>() * polygon_irradiance(triangle, point, {0, 1, 0}, kRadiance);
      const double value = frame[(j * size + i) * 4];
      expected_sum += expected;
      frame_sum += value;
      squared += (value / expected - 1.0) * (value / expected - 1.0);
      largest = std::max(largest, value / expected);
    }
  }
  const double mean_ratio = frame_sum / expected_sum;
  const double spread = std::sqrt(squared / (size * size));  // RMS relative error per pixel
  std::printf(
      "near field, 1 sample per pixel: mean %.4f of the analytic %.4f (%.3f), RMS "
      "relative error %.3f, largest pixel %.2fx its value\n",
      frame_sum / (size * size), expected_sum / (size * size), mean_ratio, spread, largest);
  // Measured (lavapipe): mean 0.961, RMS 0.58, largest 2.1x by solid angle; by area (the planted
  // fault: every triangle sampled by area) 0.990, RMS 2.1, largest 27x. The mean's tolerance is
  // 2.7 standard errors of 1024 samples of RMS 0.58.
  EXPECT_NEAR(mean_ratio, 1.0, 0.05);
  EXPECT_LT(spread, 1.0);
  EXPECT_LT(largest, 4.0);
  // Control: the floor is lit where the camera looks (not a black frame matching nothing).
  EXPECT_GT(expected_sum / (size * size), 0.5);
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
