// Mean luminance of frames and references (tests/gpu/mean_luminance.h).
#include "tests/gpu/mean_luminance.h"

#include <gtest/gtest.h>

#include "gpu_scene/gpu_scene.h"
#include "tests/gpu/gpu_test.h"

namespace ddgi::test {

double mean_luminance(const std::vector<float>& rgba) {
  double sum = 0.0;
  for (size_t i = 0; i < rgba.size(); i += 4) {
    sum += 0.2126 * rgba[i] + 0.7152 * rgba[i + 1] + 0.0722 * rgba[i + 2];
  }
  return rgba.empty() ? 0.0 : sum / double(rgba.size() / 4);
}

double path_traced_mean(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                        PathTraceView view, uint32_t spp) {
  vk::Context& context = gpu_context();
  auto gpu = GpuScene::create(context, scene);
  EXPECT_TRUE(gpu.ok()) << gpu.error().message;
  if (!gpu.ok()) return -1.0;
  auto tracer = PathTracer::create(context, **gpu, context.default_backend());
  EXPECT_TRUE(tracer.ok()) << tracer.error().message;
  if (!tracer.ok()) return -1.0;
  PathTraceSettings settings;
  settings.width = width;
  settings.height = height;
  settings.camera = camera;
  settings.jitter = false;
  settings.view = view;
  EXPECT_TRUE(tracer.value()->accumulate(settings, spp).ok());
  auto image = tracer.value()->read();
  EXPECT_TRUE(image.ok()) << image.error().message;
  return image.ok() ? mean_luminance(image->radiance) : -1.0;
}

}  // namespace ddgi::test
