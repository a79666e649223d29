// The reference path tracer on lavapipe: analytic values (white furnace, form factor), the
// raster direct pass, both backends, the view split, extreme intensities, accumulation.
// Images are tiny so that the suite stays quick on a CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "gpu_scene/gpu_scene.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"
#include "tests/gpu/white_box.h"

namespace ddgi::test {
namespace {

constexpr vk::TraceBackend kQuery = vk::TraceBackend::kRayQuery;
constexpr vk::TraceBackend kPipeline = vk::TraceBackend::kPipeline;

// Mean and standard error of the mean over an image's pixels (channel `c`). The pixels of the
// scenes below all have the same expected value, so their spread measures the noise of a
// pixel, and the standard error follows from the number of pixels.
struct PixelStats {
  double mean = 0.0;
  double standard_error = 0.0;
};
PixelStats pixel_stats(const PathTraceImage& image, int c) {
  const size_t n = size_t(image.width) * image.height;
  double sum = 0.0, sum2 = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double v = image.radiance[i * 4 + c];
    sum += v;
    sum2 += v * v;
  }
  PixelStats s;
  s.mean = sum / double(n);
  const double variance = std::max(0.0, (sum2 - sum * s.mean) / double(n - 1));
  s.standard_error = std::sqrt(variance / double(n));
  return s;
}

float max_abs_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float worst = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

float max_value(const std::vector<float>& v) {
  float worst = 0.0f;
  for (float x : v) worst = std::max(worst, x);
  return worst;
}

class PathTracerTest : public GpuTest {
 protected:
  struct Setup {
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<PathTracer> tracer;
  };
  Setup make(const Scene& scene, vk::TraceBackend backend) {
    Setup s;
    auto gpu = GpuScene::create(context(), scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    s.scene = std::move(gpu).value();
    auto tracer = PathTracer::create(context(), *s.scene, backend);
    EXPECT_TRUE(tracer.ok()) << tracer.error().message;
    s.tracer = std::move(tracer).value();
    return s;
  }
  static PathTraceImage trace(PathTracer& tracer, const PathTraceSettings& settings,
                              uint32_t samples) {
    const Status status = tracer.accumulate(settings, samples);
    EXPECT_TRUE(status.ok()) << status.error().message;
    auto image = tracer.read(Tonemap::kClamp);
    EXPECT_TRUE(image.ok()) << image.error().message;
    return std::move(image).value();
  }
  PathTraceImage trace(const Scene& scene, vk::TraceBackend backend,
                       const PathTraceSettings& settings, uint32_t samples) {
    Setup s = make(scene, backend);
    return trace(*s.tracer, settings, samples);
  }
};

PathTraceSettings tiny_settings(const Camera& camera, uint32_t size = 16) {
  PathTraceSettings settings;
  settings.width = size;
  settings.height = size;
  settings.camera = camera;
  return settings;
}

// The Cornell box plus a small emissive panel under the ceiling: punctual and area light.
Scene make_lit_cornell_box(float light_scale = 1.0f) {
  Scene scene = make_cornell_box();
  const int panel =
      add_material(scene, glm::vec3(0.0f), glm::vec3(12.0f, 11.0f, 9.0f) * light_scale, "panel");
  add_quad(scene, {-0.25f, 1.98f, 0.25f}, {-0.25f, 1.98f, -0.25f}, {0.25f, 1.98f, -0.25f},
           {0.25f, 1.98f, 0.25f}, panel);
  for (Light& light : scene.lights) light.intensity *= light_scale;
  return scene;
}

// White furnace in the repo's box (scenes/white_box.gltf, albedo and emission set in memory):
// every surface emits Le and reflects rho, so the radiance is Le / (1 - rho) everywhere. Every
// wall is an emitter, so this runs NEE, MIS and Russian roulette together (the pipeline backend at
// rho 0.2).
class PathTracerFurnaceTest
    : public PathTracerTest,
      public ::testing::WithParamInterface<std::tuple<float, vk::TraceBackend>> {};

TEST_P(PathTracerFurnaceTest, ConvergesToLeOverOneMinusRho) {
  const auto [rho, backend] = GetParam();
  const float le = 0.5f;
  const Scene scene = load_white_box(rho, le);
  ASSERT_FALSE(scene.cameras.empty());
  Setup s = make(scene, backend);
  PathTraceSettings settings = tiny_settings(scene.cameras[0]);
  // rho^201 of the series is cut: far below the noise. Roulette from the first bounce on
  // shows that it stays unbiased even when it decides almost every path's length.
  settings.max_bounces = 200;
  settings.roulette_start = 1;
  const uint32_t spp = 256;
  const PathTraceImage image = trace(*s.tracer, settings, spp);
  const double expected = le / (1.0 - rho);
  for (int c = 0; c < 3; ++c) {
    const PixelStats stats = pixel_stats(image, c);
    // 4 standard errors of 16x16x256 paths; the noise must be small enough to catch a 2% bias.
    EXPECT_NEAR(stats.mean, expected, 4.0 * stats.standard_error) << "rho " << rho;
    EXPECT_LT(stats.standard_error, 0.005 * expected) << "rho " << rho;
    EXPECT_GT(stats.standard_error, 0.0) << "the estimate cannot be noise-free";
  }

  // A bounce limit without roulette truncates the series after exactly that many terms.
  settings.max_bounces = 2;
  settings.roulette_start = 1024;
  const PathTraceImage truncated = trace(*s.tracer, settings, 16);
  const PixelStats stats = pixel_stats(truncated, 1);
  EXPECT_NEAR(stats.mean, le * (1.0 + rho + rho * rho), 4.0 * stats.standard_error + 1e-5);
}

INSTANTIATE_TEST_SUITE_P(Albedo, PathTracerFurnaceTest,
                         ::testing::Combine(::testing::Values(0.2f, 0.5f, 0.8f),
                                            ::testing::Values(kQuery)));
// The pipeline backend at rho 0.2 only: on lavapipe its long paths cost about 5 s per albedo
// at 0.5 and 0.8 (0.2 s at 0.2), too much for CI's two cores.
INSTANTIATE_TEST_SUITE_P(PipelineAlbedo, PathTracerFurnaceTest,
                         ::testing::Combine(::testing::Values(0.2f), ::testing::Values(kPipeline)));

// With one point light the direct view is deterministic (pixel centres, a single shadow ray):
// it must be the raster frame's direct pass up to the G-buffer's half-float albedo and
// 16-bit normals.
TEST_F(PathTracerTest, DirectViewMatchesRasterDirectPass) {
  Scene scene = make_cornell_box();
  Light spot;
  spot.type = LightType::kSpot;
  spot.position = {0.6f, 1.6f, 0.6f};
  spot.direction = glm::normalize(glm::vec3(-0.6f, -1.6f, -0.9f));
  spot.intensity = 2.0f;
  spot.outer_cone_angle = 0.5f;
  spot.inner_cone_angle = 0.3f;
  scene.lights.push_back(spot);
  const uint32_t size = 24;
  auto gpu = GpuScene::create(context(), scene);
  ASSERT_TRUE(gpu.ok()) << gpu.error().message;
  auto renderer = Renderer::create(context(), **gpu, nullptr, kQuery);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  FrameSettings frame;
  frame.width = frame.height = size;
  frame.camera = scene.cameras[0];
  frame.view = View::kDirect;
  frame.tonemap = Tonemap::kClamp;
  auto raster = (*renderer)->render(frame);
  ASSERT_TRUE(raster.ok()) << raster.error().message;
  auto tracer = PathTracer::create(context(), **gpu, kQuery);
  ASSERT_TRUE(tracer.ok()) << tracer.error().message;

  for (PathTraceView view : {PathTraceView::kDirect, PathTraceView::kPunctualDirect}) {
    PathTraceSettings settings = tiny_settings(scene.cameras[0], size);
    settings.view = view;
    settings.jitter = false;
    const PathTraceImage traced = trace(**tracer, settings, 2);
    ASSERT_EQ(traced.radiance.size(), raster->radiance.size());
    int lit = 0;
    for (size_t i = 0; i < traced.radiance.size(); ++i) {
      const float a = traced.radiance[i], b = raster->radiance[i];
      ASSERT_NEAR(a, b, 2e-3f * std::max(a, b) + 1e-6f) << "element " << i;
      lit += a > 0.01f ? 1 : 0;
    }
    EXPECT_GT(lit, int(size * size));  // most pixels are lit, in more than one channel
  }
}

// Irradiance at a point straight under the centre of a parallel a x a square emitter at
// height h: E = pi L F with the exact point-to-rectangle form factor (four corner rectangles).
double square_form_factor(double a, double h) {
  const double x = 0.5 * a / h;
  const double s = std::sqrt(1.0 + x * x);
  const double corner = (2.0 * x / s * std::atan(x / s)) / (2.0 * 3.14159265358979);
  return 4.0 * corner;
}

// A floor of albedo rho lit only by a square emitter facing down; the camera looks straight
// down at the point below the emitter's centre through a 1 degree field of view.
Scene make_emitter_over_floor(float side, float height, float radiance, float rho) {
  Scene scene;
  scene.source = "emitter over floor";
  const int floor = add_material(scene, glm::vec3(rho), glm::vec3(0.0f), "floor");
  add_quad(scene, {-20, 0, 20}, {20, 0, 20}, {20, 0, -20}, {-20, 0, -20}, floor);
  const int lamp = add_material(scene, glm::vec3(0.0f), glm::vec3(radiance), "lamp");
  const float r = 0.5f * side;
  add_quad(scene, {-r, height, -r}, {r, height, -r}, {r, height, r}, {-r, height, r}, lamp);
  Camera camera;
  camera.position = {0.0f, 0.5f * height, 0.0f};
  camera.forward = {0.0f, -1.0f, 0.0f};
  camera.up = {0.0f, 0.0f, -1.0f};
  camera.yfov = glm::radians(1.0f);
  scene.cameras.push_back(camera);
  return scene;
}

// Small and large emitters both converge: emitter sampling carries the small one, BSDF
// sampling most of the large one, MIS combines them.
TEST_F(PathTracerTest, EmitterLightingMatchesFormFactor) {
  struct Case {
    float side, height, radiance;
  };
  const float rho = 0.5f;
  for (const Case& c : {Case{0.2f, 2.0f, 300.0f}, Case{8.0f, 1.0f, 1.0f}}) {
    const Scene scene = make_emitter_over_floor(c.side, c.height, c.radiance, rho);
    PathTraceSettings settings = tiny_settings(scene.cameras[0]);
    settings.view = PathTraceView::kDirect;
    const PathTraceImage image = trace(scene, kQuery, settings, 64);
    const double expected = rho * c.radiance * square_form_factor(c.side, c.height);
    const PixelStats stats = pixel_stats(image, 0);
    // 4 standard errors, plus 1e-3 for the analytic value varying over the 1 degree view.
    EXPECT_NEAR(stats.mean, expected, 4.0 * stats.standard_error + 1e-3 * expected)
        << "side " << c.side;
    EXPECT_LT(stats.standard_error, 0.004 * expected) << "side " << c.side;
  }
}

// The emissive texture scales what the emitter gives, wherever it is sampled.
TEST_F(PathTracerTest, EmitterLightingUsesEmissiveTexture) {
  Scene scene = make_emitter_over_floor(2.0f, 1.0f, 1.0f, 0.5f);
  Texture grey;
  grey.name = "grey";
  grey.width = grey.height = 2;
  grey.srgb = false;
  grey.rgba8.assign(16, 128);
  scene.textures.push_back(grey);
  scene.materials[1].emissive_texture = 0;
  PathTraceSettings settings = tiny_settings(scene.cameras[0], 12);
  settings.view = PathTraceView::kDirect;
  const PathTraceImage image = trace(scene, kQuery, settings, 16);
  const double expected = 0.5 * (128.0 / 255.0) * square_form_factor(2.0, 1.0);
  EXPECT_NEAR(pixel_stats(image, 0).mean, expected, 0.01 * expected);
}

// Moving an emitter moves the light it gives: the emitter table follows instance transforms,
// and the accumulation starts over.
TEST_F(PathTracerTest, EmittersFollowInstanceTransforms) {
  const Scene scene = make_emitter_over_floor(0.2f, 1.0f, 100.0f, 0.5f);
  Setup s = make(scene, kQuery);
  PathTraceSettings settings = tiny_settings(scene.cameras[0], 8);
  settings.view = PathTraceView::kDirect;
  trace(*s.tracer, settings, 4);
  ASSERT_EQ(s.tracer->samples(), 4u);
  // Lift the lamp from 1 m to 2 m: the floor below gets about a quarter of the light.
  ASSERT_TRUE(
      s.scene->set_instance_transform(1, glm::translate(glm::mat4(1.0f), {0.0f, 1.0f, 0.0f})).ok());
  const PathTraceImage image = trace(*s.tracer, settings, 8);
  EXPECT_EQ(image.samples, 8u);
  const double expected = 0.5 * 100.0 * square_form_factor(0.2, 2.0);
  EXPECT_NEAR(pixel_stats(image, 0).mean, expected, 0.01 * expected);
}

TEST_F(PathTracerTest, BackendsGiveTheSameImage) {
  const Scene scene = make_lit_cornell_box();
  PathTraceSettings settings = tiny_settings(scene.cameras[0]);
  settings.seed = 1234;
  const PathTraceImage query = trace(scene, kQuery, settings, 4);
  const PathTraceImage pipeline = trace(scene, kPipeline, settings, 4);
  // Same rays, same random numbers: only float rounding may differ.
  EXPECT_LE(max_abs_difference(query.radiance, pipeline.radiance),
            1e-4f * max_value(query.radiance));
  // Lit and not flat, or the agreement means nothing. Measured: mean 0.490, range 0 .. 12.
  EXPECT_TRUE(is_nontrivial(query.radiance, 0.1, 1.0, 4, 3));
}

// Full = direct + indirect, and = punctual direct + field indirect: the same paths, split.
TEST_F(PathTracerTest, ViewsSplitTheFullImage) {
  const Scene scene = make_lit_cornell_box();
  Setup s = make(scene, kQuery);
  PathTraceSettings settings = tiny_settings(scene.cameras[0]);
  settings.seed = 99;
  auto traced = [&](PathTraceView view) {
    settings.view = view;
    return trace(*s.tracer, settings, 4).radiance;
  };
  const std::vector<float> full = traced(PathTraceView::kFull);
  const std::vector<float> direct = traced(PathTraceView::kDirect);
  const std::vector<float> indirect = traced(PathTraceView::kIndirect);
  const std::vector<float> punctual = traced(PathTraceView::kPunctualDirect);
  const std::vector<float> field = traced(PathTraceView::kFieldIndirect);
  double direct_sum = 0.0, indirect_sum = 0.0, punctual_sum = 0.0;
  for (size_t i = 0; i < full.size(); i += 4) {
    for (size_t c = i; c < i + 3; ++c) {
      const float tolerance = 1e-5f * (1.0f + full[c]);
      ASSERT_NEAR(full[c], direct[c] + indirect[c], tolerance) << "element " << c;
      ASSERT_NEAR(full[c], punctual[c] + field[c], tolerance) << "element " << c;
      ASSERT_GE(direct[c], punctual[c] - tolerance) << "element " << c;
      direct_sum += direct[c];
      indirect_sum += indirect[c];
      punctual_sum += punctual[c];
    }
  }
  // Every part carries light: the panel adds direct light beyond the point light's.
  EXPECT_GT(indirect_sum, 0.1 * direct_sum);
  EXPECT_GT(direct_sum, 1.05 * punctual_sum);
  EXPECT_GT(punctual_sum, 0.0);
}

// Radiance stays finite and scales linearly over 12 orders of magnitude of light: the same
// seed takes the same paths whatever the intensity.
TEST_F(PathTracerTest, ExtremeIntensitiesStayFinite) {
  auto make_scene = [](float scale) {
    Scene scene = make_lit_cornell_box(scale);
    Light sphere;
    sphere.position = {0.5f, 1.0f, 0.3f};
    sphere.radius = 0.1f;
    sphere.intensity = scale;
    scene.lights.push_back(sphere);
    Light sun;
    sun.type = LightType::kDirectional;
    sun.direction = glm::normalize(glm::vec3(0.2f, -1.0f, -0.4f));
    sun.intensity = scale;
    scene.lights.push_back(sun);
    scene.environment.color = glm::vec3(scale);
    return scene;
  };
  PathTraceSettings settings = tiny_settings(make_cornell_box().cameras[0], 12);
  std::vector<double> sums;
  for (float scale : {1e-6f, 1e6f}) {
    const PathTraceImage image = trace(make_scene(scale), kQuery, settings, 4);
    double sum = 0.0;
    for (float v : image.radiance) {
      ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << "scale " << scale << ": " << v;
      sum += v;
    }
    sums.push_back(sum - double(image.width) * image.height);  // without alpha
  }
  EXPECT_GT(sums[0], 0.0);
  EXPECT_NEAR(sums[1] / sums[0], 1e12, 1e12 * 1e-3);
}

// Samples batched differently give the same mean; a new camera starts over.
TEST_F(PathTracerTest, AccumulatesProgressively) {
  const Scene scene = make_lit_cornell_box();
  Setup s = make(scene, kQuery);
  PathTraceSettings settings = tiny_settings(scene.cameras[0], 8);
  const PathTraceImage once = trace(*s.tracer, settings, 6);
  s.tracer->reset();
  trace(*s.tracer, settings, 2);
  const PathTraceImage twice = trace(*s.tracer, settings, 4);
  EXPECT_EQ(twice.samples, 6u);
  EXPECT_LE(max_abs_difference(once.radiance, twice.radiance), 1e-5f * max_value(once.radiance));

  settings.camera.position.x += 0.1f;
  const PathTraceImage moved = trace(*s.tracer, settings, 1);
  EXPECT_EQ(moved.samples, 1u);
  EXPECT_FALSE(s.tracer->accumulate(settings, 0).ok());
  settings.max_bounces = 5000;
  EXPECT_FALSE(s.tracer->accumulate(settings, 1).ok());
}

}  // namespace
}  // namespace ddgi::test
