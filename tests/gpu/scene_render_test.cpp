// Scene files through the loader and the renderer on lavapipe: the repo's scenes and the real
// scenes in ../shared/scenes render on both tracing backends, and the backends agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "tests/gpu/gpu_test.h"

namespace ddgi::test {
namespace {

const std::string kRepo = DDGI_SOURCE_DIR;

struct BackendPair {
  FrameResult query;
  FrameResult pipeline;
};

class SceneRenderTest : public GpuTest {
 protected:
  // With `headlight`, a point light just above the camera is added to the scene's lights.
  BackendPair render_both(const std::string& path, uint32_t width, uint32_t height,
                          bool headlight = false) {
    auto scene = load_scene(path);
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    if (!scene.ok()) return {};
    if (headlight) {
      // Intensity diagonal^2 gives irradiance >= 1 on everything within a diagonal of it,
      // whatever the scene's scale.
      const Camera camera = default_camera(*scene);
      const Bounds bounds = scene->world_bounds();
      const float diagonal = glm::length(bounds.max - bounds.min);
      Light light;
      light.name = "test_headlight";
      light.position = camera.position + 0.02f * diagonal * camera.up;
      light.intensity = diagonal * diagonal;
      scene->lights.push_back(light);
    }
    auto gpu = GpuScene::create(context(), *scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    if (!gpu.ok()) return {};
    FrameSettings settings;
    settings.width = width;
    settings.height = height;
    settings.camera = default_camera(*scene);
    BackendPair pair;
    for (vk::TraceBackend backend : {vk::TraceBackend::kRayQuery, vk::TraceBackend::kPipeline}) {
      auto renderer = Renderer::create(context(), **gpu, nullptr, backend);
      EXPECT_TRUE(renderer.ok()) << renderer.error().message;
      if (!renderer.ok()) return {};
      auto frame = (*renderer)->render(settings);
      EXPECT_TRUE(frame.ok()) << frame.error().message;
      if (!frame.ok()) return {};
      (backend == vk::TraceBackend::kRayQuery ? pair.query : pair.pipeline) =
          std::move(frame).value();
    }
    return pair;
  }
};

// Largest per-channel difference relative to the brighter of the two values (and 1e-3 absolute
// so black pixels do not divide by zero).
float max_relative_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float worst = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) {
    const float scale = std::max({std::abs(a[i]), std::abs(b[i]), 1e-3f});
    worst = std::max(worst, std::abs(a[i] - b[i]) / scale);
  }
  return worst;
}

bool all_finite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

// The backends trace the same rays against the same structures with the same shading code:
// they may differ by float rounding only (1e-4 relative).
constexpr float kBackendTolerance = 1e-4f;

TEST_F(SceneRenderTest, RepoCornellBoxBackendsAgree) {
  const BackendPair pair = render_both(kRepo + "/scenes/cornell_box.gltf", 64, 48);
  ASSERT_EQ(pair.query.radiance.size(), size_t(64 * 48 * 4));
  ASSERT_EQ(pair.pipeline.radiance.size(), pair.query.radiance.size());
  EXPECT_LE(max_relative_difference(pair.query.radiance, pair.pipeline.radiance),
            kBackendTolerance);
  EXPECT_TRUE(all_finite(pair.query.radiance));
  // Lit and not flat, or the agreement means nothing. Measured: mean 0.237, range 0 .. 60.0.
  EXPECT_TRUE(is_nontrivial(pair.query.radiance, 0.05, 0.5, 4, 3));
}

// The real scenes made by others (../shared/scenes), through the repo's sidecars. Without an
// irradiance field a frame shows punctual lights and visible emitters only: veach_ajar and
// staircase, lit by emitters the camera does not see, rendered black on both backends (measured
// mean 0, range 0), so their agreement proved nothing. A headlight lights what the camera sees
// (primary and shadow rays on both backends) in every scene.
class RealSceneTest : public SceneRenderTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(RealSceneTest, RendersOnBothBackendsAlike) {
  const std::string path = kRepo + "/scenes/" + GetParam();
  if (!std::filesystem::exists(kRepo + "/../shared/scenes")) GTEST_SKIP() << "no ../shared/scenes";
  const BackendPair pair = render_both(path, 48, 27, /*headlight=*/true);
  ASSERT_FALSE(pair.query.radiance.empty());
  EXPECT_LE(max_relative_difference(pair.query.radiance, pair.pipeline.radiance),
            kBackendTolerance);
  EXPECT_TRUE(all_finite(pair.query.radiance));
  // Lit by the headlight at least, so never black or flat. Measured: means from 0.112
  // (cornell_kajiya) to 77.3 (lights_punctual), the smallest range 0 .. 3.23 (veach_ajar).
  const ValueSpread spread = value_spread(pair.query.radiance, 4, 3);
  std::printf("%s: mean %.4f, range %.4f .. %.4f\n", GetParam(), spread.mean, spread.min,
              spread.max);
  EXPECT_TRUE(is_nontrivial(pair.query.radiance, 0.02, 1.0, 4, 3));
}

INSTANTIATE_TEST_SUITE_P(Shared, RealSceneTest,
                         ::testing::Values("cornell_kajiya.ddgi.json", "cornell_nvpro.ddgi.json",
                                           "lights_punctual.ddgi.json", "veach_ajar.ddgi.json",
                                           "staircase.ddgi.json", "modern_hall.ddgi.json",
                                           "living_room.ddgi.json"));

}  // namespace
}  // namespace ddgi::test
