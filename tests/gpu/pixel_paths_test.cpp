// Paths per pixel (field parameter pixel_paths, render/pixel_paths.glsl) on cornell_nvpro, the
// scene whose light no probe grid holds: an emitter slab 0.27 m under an albedo-1 ceiling, whose
// slot shines 5-7x the emitter (docs/results/default-energy.md). The field at the pixel keeps
// about 0.55 of the path tracer's mean; long paths per pixel bring it back. Frames and references
// are made here, with the field of the same updates, turned from one to the other on renderers
// made before (their kernel is built when first asked), on both tracing backends.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

#include "gi/gi_stack.h"
#include "gpu_scene/camera_fit.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/mean_luminance.h"
#include "tests/gpu/shadow_test_support.h"

namespace ddgi::test {
namespace {

class PixelPathsTest : public GpuTest {
 protected:
  static constexpr uint32_t kWidth = 64, kHeight = 36;
};

TEST_F(PixelPathsTest, BringBackTheLightOfASlotNoProbeGridHolds) {
  if (!std::filesystem::exists(std::string(DDGI_SOURCE_DIR) + "/../shared/scenes")) {
    GTEST_SKIP() << "no ../shared/scenes";
  }
  const Scene scene = load_repo_scene("cornell_nvpro.ddgi.json");
  auto fitted = fitted_gi_options(scene, true, DirectMode::kTracedShadows, {}, {},
                                  context().default_backend());
  ASSERT_TRUE(fitted.ok()) << fitted.error().message;
  const Camera camera = default_camera(scene);
  const double full_ref =
      path_traced_mean(scene, camera, kWidth, kHeight, PathTraceView::kFull, 256);
  const double indirect_ref =
      path_traced_mean(scene, camera, kWidth, kHeight, PathTraceView::kFieldIndirect, 256);
  ASSERT_GT(indirect_ref, 0.01 * full_ref);  // control: the field part is not black

  FieldSetup setup = make_field_setup(scene, fitted->field, context().default_backend());
  ASSERT_NE(setup.field, nullptr);
  ASSERT_TRUE(setup.gi->warm_up(64).ok());
  // Renderers made before the field asks for paths per pixel: each builds its kernel then.
  auto query = Renderer::create(context(), *setup.scene, setup.field, vk::TraceBackend::kRayQuery);
  ASSERT_TRUE(query.ok()) << query.error().message;
  auto pipeline =
      Renderer::create(context(), *setup.scene, setup.field, vk::TraceBackend::kPipeline);
  ASSERT_TRUE(pipeline.ok()) << pipeline.error().message;
  // Mean/ref of the full frame and of the indirect view, without further updates.
  auto ratios = [&](Renderer& renderer) -> std::pair<double, double> {
    auto mean_of = [&](View view) {
      FrameSettings settings;
      settings.width = kWidth;
      settings.height = kHeight;
      settings.camera = camera;
      settings.view = view;
      auto frame = renderer.render(settings);
      EXPECT_TRUE(frame.ok()) << frame.error().message;
      return frame.ok() ? mean_luminance(frame->radiance) : -1.0;
    };
    return {mean_of(View::kFull) / full_ref, mean_of(View::kIndirect) / indirect_ref};
  };
  const auto [full_field, indirect_field] = ratios(**query);
  IrradianceFieldParams params = setup.field->params();
  params.pixel_paths = 64;
  params.pixel_path_vertices = 32;
  ASSERT_TRUE(setup.field->set_params(params).ok());
  const auto [full_paths, indirect_paths] = ratios(**query);
  // The same paths on the other backend (one GLSL source; the same random numbers).
  const auto [full_pipeline, indirect_pipeline] = ratios(**pipeline);
  std::printf(
      "mean/ref (full / indirect): field at the pixel %.3f / %.3f, %u paths of %u "
      "vertices per pixel %.3f / %.3f (ray queries), %.3f / %.3f (pipeline)\n",
      full_field, indirect_field, params.pixel_paths, params.pixel_path_vertices, full_paths,
      indirect_paths, full_pipeline, indirect_pipeline);
  // Control: the field loses the slot's light here (measured 0.533 / 0.468).
  EXPECT_LT(full_field, 0.8);
  EXPECT_LT(indirect_field, 0.8);
  // Measured 0.930 / 0.920. The slot's light comes along rare long paths, so a few paths per
  // pixel over this small frame's 2304 pixels undershoot it, and the mean climbs with the paths
  // (4: 0.82, 16: 0.88, 32: 0.89, 64: 0.93); 64, the most the parameter allows, within 10%.
  EXPECT_NEAR(full_paths, 1.0, 0.10);
  EXPECT_NEAR(indirect_paths, 1.0, 0.10);
  // Measured equal to the printed digits; 0.5%: a path may part where the backends round apart.
  EXPECT_NEAR(full_pipeline, full_paths, 0.005);
  EXPECT_NEAR(indirect_pipeline, indirect_paths, 0.005);
}

}  // namespace
}  // namespace ddgi::test
