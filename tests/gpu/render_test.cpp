// The renderer on lavapipe: both tracing backends, the same images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"

namespace ddgi::test {
namespace {

class RenderTest : public GpuTest {
 protected:
  FrameResult render(const Scene& scene, vk::TraceBackend backend, FrameSettings settings) {
    auto gpu = GpuScene::create(context(), scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    auto renderer = Renderer::create(context(), **gpu, nullptr, backend);
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    auto frame = (*renderer)->render(settings);
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    return std::move(frame).value();
  }
};

float max_abs_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float worst = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

TEST_F(RenderTest, BackendsAgreeOnCornellBox) {
  const Scene scene = make_cornell_box();
  FrameSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.camera = scene.cameras[0];
  const FrameResult query = render(scene, vk::TraceBackend::kRayQuery, settings);
  const FrameResult pipeline = render(scene, vk::TraceBackend::kPipeline, settings);
  ASSERT_EQ(query.radiance.size(), pipeline.radiance.size());
  // Same hits, same shading code: only float rounding may differ.
  EXPECT_LE(max_abs_difference(query.radiance, pipeline.radiance), 1e-5f);
  // Not black, not flat. Measured: mean 0.239, range 0 .. 60.0 (the light).
  EXPECT_TRUE(is_nontrivial(query.radiance, 0.05, 0.5, 4, 3));
  // Not trivially black or uniform: the back wall is lit, the left wall is red, the right green.
  auto pixel = [&](int x, int y) {
    const float* p = &query.radiance[(size_t(y) * 64 + x) * 4];
    return glm::vec3(p[0], p[1], p[2]);
  };
  EXPECT_GT(pixel(32, 12).g, 0.05f);
  EXPECT_GT(pixel(8, 20).r, 4.0f * pixel(8, 20).g);
  EXPECT_GT(pixel(56, 20).g, 2.0f * pixel(56, 20).r);
}

}  // namespace
}  // namespace ddgi::test
