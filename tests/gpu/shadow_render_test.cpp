// The direct-light modes in frames (docs/shadow-field.md): the shadow-field mode approximates
// shadow rays, the AO mode adds the sky only without an irradiance field, soft shadows sharpen
// with more samples, the modes refuse to run without a shadow field, both backends agree.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>

#include "gi/irradiance_field.h"
#include "render/renderer.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/shadow_test_support.h"

namespace ddgi::test {
namespace {

// Mean |a - b| over the RGB of two linear frames, relative to b's mean.
float relative_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double diff = 0.0, sum = 0.0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (i % 4 == 3) continue;
    diff += std::abs(a[i] - b[i]);
    sum += std::abs(b[i]);
  }
  return sum > 0.0 ? static_cast<float>(diff / sum) : 0.0f;
}

class ShadowRenderTest : public GpuTest {
 protected:
  struct Setup {
    Scene scene;
    std::unique_ptr<GpuScene> gpu;
    std::unique_ptr<IrradianceField> field;
    std::unique_ptr<ShadowField> shadow;
    std::unique_ptr<Renderer> renderer;
  };
  Setup make(Scene scene, bool with_shadow_field, bool with_gi,
             vk::TraceBackend backend = vk::TraceBackend::kRayQuery) {
    Setup s;
    s.scene = std::move(scene);
    auto gpu = GpuScene::create(context(), s.scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    if (!gpu.ok()) return s;
    s.gpu = std::move(gpu).value();
    if (with_shadow_field) {
      auto shadow = ShadowField::create(context(), *s.gpu, box_on_floor_grid(), backend);
      EXPECT_TRUE(shadow.ok()) << shadow.error().message;
      if (shadow.ok()) s.shadow = std::move(shadow).value();
    }
    if (with_gi) {
      IrradianceFieldParams params = fit_grid_to_bounds(s.scene.world_bounds(), 64);
      params.rays_per_probe = 64;
      auto field = IrradianceField::create(context(), *s.gpu, params, backend, s.shadow.get());
      EXPECT_TRUE(field.ok()) << field.error().message;
      if (field.ok()) s.field = std::move(field).value();
    }
    auto renderer = Renderer::create(context(), *s.gpu, s.field.get(), backend, s.shadow.get());
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    if (renderer.ok()) s.renderer = std::move(renderer).value();
    return s;
  }

  std::vector<float> render(Setup& s, DirectMode mode, uint32_t light_samples = 1,
                            uint32_t shadow_updates = 16) {
    FrameSettings settings;
    settings.width = 96;
    settings.height = 72;
    settings.camera = s.scene.cameras.at(0);
    settings.view = View::kDirect;
    settings.direct_mode = mode;
    settings.light_samples = light_samples;
    auto frame =
        render_updated(*s.renderer, settings, s.field.get(), s.shadow.get(), {0, shadow_updates});
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    return frame.ok() ? frame->radiance : std::vector<float>{};
  }
};

// The shadow-field frame is close to the shadow-rays frame; the unshadowed one is not (so the
// metric sees shadows at all). Measured: 0.026 vs 0.105 relative mean difference.
TEST_F(ShadowRenderTest, ShadowFieldModeApproximatesShadowRays) {
  Setup s = make(load_repo_scene("box_on_floor.gltf"), true, false);
  ASSERT_TRUE(s.renderer);
  const auto traced = render(s, DirectMode::kTracedShadows);
  const auto field = render(s, DirectMode::kShadowField);
  const auto unshadowed = render(s, DirectMode::kUnshadowed);
  const float field_error = relative_difference(field, traced);
  const float unshadowed_error = relative_difference(unshadowed, traced);
  std::printf("direct frame vs shadow rays: shadow field %.4f, unshadowed %.4f\n", field_error,
              unshadowed_error);
  EXPECT_LT(field_error, 0.1f);
  EXPECT_GT(unshadowed_error, 3.0f * field_error);
}

TEST_F(ShadowRenderTest, ShadowModesNeedAShadowField) {
  Setup s = make(load_repo_scene("box_on_floor.gltf"), false, false);
  ASSERT_TRUE(s.renderer);
  for (DirectMode mode : {DirectMode::kShadowField, DirectMode::kAmbientOcclusion}) {
    FrameSettings settings;
    settings.width = 8;
    settings.height = 8;
    settings.direct_mode = mode;
    auto frame = s.renderer->render(settings);
    ASSERT_FALSE(frame.ok());
    EXPECT_EQ(frame.error().code, ErrorCode::kFailedPrecondition);
    EXPECT_NE(frame.error().message.find("shadow field"), std::string::npos);
  }
}

// A spherical light's penumbra from one shadow ray per pixel is noise; 16 rays come much closer
// to a 64-ray image.
TEST_F(ShadowRenderTest, MoreLightSamplesSmoothSoftShadows) {
  Scene scene = load_repo_scene("box_on_floor.gltf");
  scene.lights[0].radius = 0.4f;
  Setup s = make(std::move(scene), false, false);
  ASSERT_TRUE(s.renderer);
  const auto one = render(s, DirectMode::kTracedShadows, 1);
  const auto sixteen = render(s, DirectMode::kTracedShadows, 16);
  const auto reference = render(s, DirectMode::kTracedShadows, 64);
  const float e1 = relative_difference(one, reference);
  const float e16 = relative_difference(sixteen, reference);
  std::printf("soft shadows vs 64 samples: 1 sample %.4f, 16 samples %.4f\n", e1, e16);
  EXPECT_LT(e16, 0.5f * e1);
}

// Sky light through AO: with a white sky, no lights and GI off, the floor far from the cube
// reflects about its albedo (0.8) and darkens at the cube's foot; with an irradiance field the
// sky arrives through the field instead, and the AO mode adds nothing (no double counting).
TEST_F(ShadowRenderTest, AoModeAddsTheSkyOnlyWithoutGi) {
  Scene scene = load_repo_scene("box_on_floor.gltf");
  scene.lights.clear();
  scene.environment.color = glm::vec3(1.0f);
  for (bool gi : {false, true}) {
    Setup s = make(scene, true, gi);
    ASSERT_TRUE(s.renderer);
    ASSERT_TRUE(s.shadow->update(16, DirectMode::kAmbientOcclusion).ok());
    auto answers = s.shadow->query(box_floor_points(-3.0f, 3.0f, -3.0f, 3.0f, 0.5f));
    ASSERT_TRUE(answers.ok());
    const auto frame = render(s, DirectMode::kAmbientOcclusion, 1, 1);
    ASSERT_FALSE(frame.empty());
    // The centre pixel lies on the floor inside the (would-be) shadow region, next to the cube.
    const size_t centre = (size_t(36) * 96 + 48) * 4;
    std::printf("AO mode, GI %s: centre pixel %.4f\n", gi ? "on" : "off", frame[centre]);
    if (gi) {
      EXPECT_EQ(frame[centre], 0.0f);
    } else {
      EXPECT_GT(frame[centre], 0.3f);
      EXPECT_LT(frame[centre], 0.8f);
    }
  }
}

// The passes that read the shadow field run the same on both backends: the direct pass, and
// with GI the irradiance field's probe-ray shading (field_shade compiled with the shadow field
// as set 3) and the indirect pass over that field.
TEST_F(ShadowRenderTest, BackendsAgreeInShadowFieldMode) {
  std::vector<float> direct[2], full[2];
  for (int b = 0; b < 2; ++b) {
    const vk::TraceBackend backend =
        b == 0 ? vk::TraceBackend::kRayQuery : vk::TraceBackend::kPipeline;
    Setup s = make(load_repo_scene("box_on_floor.gltf"), true, false, backend);
    ASSERT_TRUE(s.renderer);
    direct[b] = render(s, DirectMode::kShadowField, 1, 4);
    Setup gi = make(load_repo_scene("box_on_floor.gltf"), true, true, backend);
    ASSERT_TRUE(gi.renderer);
    FrameSettings settings;
    settings.width = 48;
    settings.height = 36;
    settings.camera = gi.scene.cameras.at(0);
    settings.direct_mode = DirectMode::kShadowField;
    auto frame = render_updated(*gi.renderer, settings, gi.field.get(), gi.shadow.get(), {3, 2});
    ASSERT_TRUE(frame.ok()) << frame.error().message;
    full[b] = frame->radiance;
  }
  // Agreement means nothing on black frames (relative_difference is 0 for them). Measured on
  // the query backend: direct mean 0.156, range 0 .. 1.285; full mean 0.161, range 0 .. 1.235.
  EXPECT_TRUE(is_nontrivial(direct[0], 0.04, 0.4, 4, 3)) << "direct frame";
  EXPECT_TRUE(is_nontrivial(full[0], 0.04, 0.4, 4, 3)) << "full frame";
  const float direct_difference = relative_difference(direct[1], direct[0]);
  const float full_difference = relative_difference(full[1], full[0]);
  std::printf("backends, shadow-field mode: direct %.2e, full with GI %.2e\n", direct_difference,
              full_difference);
  EXPECT_LT(direct_difference, 1e-5f);
  EXPECT_LT(full_difference, 1e-4f);
}

// Probe rays of the irradiance field are lit in the chosen mode: unshadowed light reaches the
// cube's shadow on the floor, traced shadow rays keep it out, and with a shadow field bound its
// mode reads the field there instead of tracing (docs/shadow-field.md, "Probe rays").
TEST_F(ShadowRenderTest, ProbeRaysAreShadedInTheChosenMode) {
  Scene scene = load_repo_scene("box_on_floor.gltf");
  auto gpu = GpuScene::create(context(), scene);
  ASSERT_TRUE(gpu.ok()) << gpu.error().message;
  IrradianceFieldParams params;
  params.origin = {-2.75f, 0.25f, -2.75f};
  params.spacing = glm::vec3(0.5f);
  params.counts = {12, 3, 12};
  params.rays_per_probe = 64;
  auto floor_points = [](float x0, float x1) {
    std::vector<IrradianceQuery> points;
    for (float x = x0; x < x1; x += 0.2f) {
      for (float z = -0.5f; z <= 0.5f; z += 0.25f) {
        points.push_back({{x, 0.0f, z}, {0, 1, 0}, {0, 1, 0}});
      }
    }
    return points;
  };
  const std::vector<IrradianceQuery> shadowed = floor_points(0.7f, 1.7f);  // behind the cube
  const std::vector<IrradianceQuery> lit = floor_points(-2.0f, -1.0f);     // facing the light

  auto warmed =
      ShadowField::create(context(), **gpu, box_on_floor_grid(), context().default_backend());
  ASSERT_TRUE(warmed.ok()) << warmed.error().message;
  ASSERT_TRUE((*warmed)->update(16, DirectMode::kShadowField).ok());
  // Never updated: its maps start lit (visibility 1), so the cube casts no shadow in it.
  auto empty =
      ShadowField::create(context(), **gpu, box_on_floor_grid(), context().default_backend());
  ASSERT_TRUE(empty.ok()) << empty.error().message;

  struct Case {
    const char* name;
    DirectMode mode;  // the mode the update is run in (the frame's)
    const ShadowField* shadow;
    std::optional<DirectMode> probe_direct;  // the field parameter
    float in_shadow = 0.0f, in_light = 0.0f;
    uint64_t rays = 0;
  };
  Case cases[] = {
      {"shadow rays", DirectMode::kTracedShadows, nullptr, {}},
      {"unshadowed", DirectMode::kUnshadowed, nullptr, {}},
      {"shadow field", DirectMode::kShadowField, warmed->get(), {}},
      {"empty shadow field", DirectMode::kShadowField, empty->get(), {}},
      {"shadow field, none bound", DirectMode::kShadowField, nullptr, {}},
      {"probe_direct=unshadowed", DirectMode::kTracedShadows, nullptr, DirectMode::kUnshadowed},
      {"probe_direct=shadow-field", DirectMode::kTracedShadows, warmed->get(),
       DirectMode::kShadowField}};
  for (Case& c : cases) {
    IrradianceFieldParams case_params = params;
    case_params.probe_direct = c.probe_direct;
    auto field = IrradianceField::create(context(), **gpu, case_params, context().default_backend(),
                                         c.shadow);
    ASSERT_TRUE(field.ok()) << field.error().message;
    ASSERT_TRUE((*field)->update(4, c.mode).ok());
    c.rays = (*field)->rays_per_update();
    for (auto [points, mean] : {std::pair{&shadowed, &c.in_shadow}, std::pair{&lit, &c.in_light}}) {
      auto answers = (*field)->query(*points);
      ASSERT_TRUE(answers.ok()) << answers.error().message;
      for (const glm::vec3& v : *answers) *mean += v.y / float(answers->size());
    }
    std::printf("%-26s field irradiance in the shadow %.5f, in the light %.5f, %llu rays\n", c.name,
                c.in_shadow, c.in_light, static_cast<unsigned long long>(c.rays));
  }
  const Case &traced = cases[0], &unshadowed = cases[1], &field = cases[2], &empty_field = cases[3],
             &unbound = cases[4], &own_unshadowed = cases[5], &own_field = cases[6];
  EXPECT_GT(unshadowed.in_shadow, 1.5f * traced.in_shadow);
  // The field's visibility approximates the traced one: within 20% of its irradiance.
  EXPECT_NEAR(field.in_shadow, traced.in_shadow, 0.2f * traced.in_shadow);
  EXPECT_NEAR(field.in_light, traced.in_light, 0.2f * traced.in_light);
  // It is read, not traced: through an empty field the light reaches the shadow as unshadowed
  // light does, and no shadow rays are counted.
  EXPECT_GT(empty_field.in_shadow, 1.5f * traced.in_shadow);
  EXPECT_LT(field.rays, traced.rays);
  EXPECT_EQ(field.rays, unshadowed.rays);
  // Without a shadow field the mode traces shadow rays at probe-ray hits.
  EXPECT_NEAR(unbound.in_shadow, traced.in_shadow, 1e-5f * std::max(traced.in_shadow, 1.0f));
  EXPECT_EQ(unbound.rays, traced.rays);
  // The field parameter probe_direct lights probe rays in its own mode, whatever mode the update
  // runs in: the same kernels on the same inputs, so the same values.
  EXPECT_EQ(own_unshadowed.in_shadow, unshadowed.in_shadow);
  EXPECT_EQ(own_unshadowed.rays, unshadowed.rays);
  EXPECT_EQ(own_field.in_shadow, field.in_shadow);
  EXPECT_EQ(own_field.in_light, field.in_light);
  EXPECT_EQ(own_field.rays, field.rays);
}

// Frames update the shadow field when the irradiance field's probe rays read it (probe_direct),
// even if the frame itself traces shadow rays; otherwise they leave it alone.
TEST_F(ShadowRenderTest, FramesUpdateTheShadowFieldTheProbeRaysRead) {
  for (bool probes_read_it : {false, true}) {
    Setup s = make(load_repo_scene("box_on_floor.gltf"), true, false);
    ASSERT_TRUE(s.shadow);
    IrradianceFieldParams params = fit_grid_to_bounds(s.scene.world_bounds(), 27);
    params.rays_per_probe = 16;
    if (probes_read_it) params.probe_direct = DirectMode::kShadowField;
    auto field = IrradianceField::create(context(), *s.gpu, params, context().default_backend(),
                                         s.shadow.get());
    ASSERT_TRUE(field.ok()) << field.error().message;
    auto renderer = Renderer::create(context(), *s.gpu, field->get(), context().default_backend(),
                                     s.shadow.get());
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    FrameSettings settings;
    settings.width = 8;
    settings.height = 8;
    settings.direct_mode = DirectMode::kTracedShadows;
    ASSERT_TRUE(render_updated(**renderer, settings, field->get(), s.shadow.get(), {1, 2}).ok());
    EXPECT_EQ(s.shadow->updates(), probes_read_it ? 2u : 0u);
    EXPECT_EQ((*field)->updates(), 1u);
  }
}

}  // namespace
}  // namespace ddgi::test
