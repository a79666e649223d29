// A session's choice (tools/field_choice.h) on the Cornell box, made as a session makes it: the
// calibration over the fitted field at the server's default budget, the costs injected
// (lavapipe's times mean nothing) as an H100 measured them. Its light is checked by frames and
// path-traced references made here without the calibration's code, at another size, sample count
// and warm-up; and ddgi-eval --session-defaults end to end. The rule alone, on hand-made tables:
// tests/unit/tools/field_choice_test.cpp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

#include "gi/gi_stack.h"
#include "gi/param_table.h"
#include "gpu_scene/camera_fit.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "tests/gpu/cli_run.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/mean_luminance.h"
#include "tests/gpu/shadow_test_support.h"
#include "tools/field_choice.h"

namespace ddgi::test {
namespace {

class FieldEnergyTest : public GpuTest {
 protected:
  static constexpr uint32_t kWidth = 64, kHeight = 36;

  // The path tracer's mean luminance of `view`, at the check's own size.
  static double reference_mean(const Scene& scene, PathTraceView view) {
    return path_traced_mean(scene, default_camera(scene), kWidth, kHeight, view, 512);
  }

  // The full frame's and the indirect view's mean luminance of a field of `params`, 96 updates in.
  std::pair<double, double> frame_means(const Scene& scene, const IrradianceFieldParams& params) {
    FieldSetup setup = make_field_setup(scene, params, context().default_backend());
    EXPECT_NE(setup.field, nullptr);
    if (!setup.field) return {-1.0, -1.0};
    EXPECT_TRUE(setup.gi->warm_up(96).ok());
    auto renderer =
        Renderer::create(context(), *setup.scene, setup.field, context().default_backend());
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    if (!renderer.ok()) return {-1.0, -1.0};
    auto mean_of = [&](View view) {
      FrameSettings settings;
      settings.width = kWidth;
      settings.height = kHeight;
      settings.camera = default_camera(scene);
      settings.view = view;
      auto frame = render_updated(**renderer, settings, setup.field);
      EXPECT_TRUE(frame.ok()) << frame.error().message;
      return frame.ok() ? mean_luminance(frame->radiance) : -1.0;
    };
    return {mean_of(View::kFull), mean_of(View::kIndirect)};
  }
};

TEST_F(FieldEnergyTest, ACalibratedSessionKeepsTheCornellBoxsLight) {
  const Scene scene = load_repo_scene("cornell_box.gltf");
  auto fitted = fitted_gi_options(scene, true, DirectMode::kTracedShadows, {}, {},
                                  context().default_backend());
  ASSERT_TRUE(fitted.ok()) << fitted.error().message;
  GiStackOptions options = *fitted;
  // Rays and paths per pixel fixed as a session may fix them: the gathering axis and the coarse
  // grid are what is chosen from (6 candidates; lavapipe measures each in seconds).
  const std::vector<std::string> fixed = {"rays_per_probe=64", "pixel_paths=0"};
  ASSERT_TRUE(field_param_table().apply(options.field, fixed).ok());
  const auto candidates = tools::budget_candidates(scene, options.field, fixed);
  ASSERT_EQ(candidates.size(), 6u);
  tools::CalibrationOptions calibration;
  calibration.width = 96;  // lavapipe: a small frame, a short warm-up
  calibration.height = 54;
  calibration.reference_spp = 128;
  calibration.warmup_updates = 48;
  // An H100's 1080p costs: the static default, bias, one bounce (x2.4 the update), one bounce
  // with bias, with gamma 1, the coarse grid.
  calibration.injected_ms = {1.4, 1.4, 3.4, 3.4, 3.4, 1.1};
  tools::BudgetCache cache;
  auto choice = tools::apply_budget(context(), scene, default_camera(scene), options, fixed,
                                    tools::kDefaultBudgetMs, calibration, cache);
  ASSERT_TRUE(choice.ok()) << choice.error().message;
  std::printf("choice: %s\n", tools::describe(*choice).c_str());
  EXPECT_TRUE(choice->budget_met);
  EXPECT_TRUE(choice->energy_met);
  // The errors are measured, with their noise: FLIP in (0, 1), a noise above 0 and below it.
  EXPECT_GT(choice->chosen.flip, 0.0);
  EXPECT_LT(choice->chosen.flip, 1.0);
  EXPECT_GT(choice->chosen.flip_noise, 0.0);
  EXPECT_LT(choice->chosen.flip_noise, choice->chosen.flip);
  EXPECT_GT(choice->chosen.mean_ratio_noise, 0.0);
  // The choice is in the options a session's field is then made from.
  IrradianceFieldParams expected = fitted->field;
  ASSERT_TRUE(field_param_table().apply(expected, fixed).ok());
  ASSERT_TRUE(field_param_table().apply(expected, choice->chosen.candidate.assignments).ok());
  EXPECT_EQ(options.field.probe_bounces, expected.probe_bounces);
  EXPECT_EQ(options.field.self_shadow_bias, expected.self_shadow_bias);
  EXPECT_EQ(options.field.counts, expected.counts);
  EXPECT_EQ(options.field.rays_per_probe, 64u) << "fixed by the session";

  // The check, made without the calibration's code: the chosen field's frame against a
  // reference of 512 samples at 64x36 after 96 updates, within 5%; and the calibration's own
  // ratio within 3% of it (another size, warm-up and reference).
  const double full_ref = reference_mean(scene, PathTraceView::kFull);
  ASSERT_GT(full_ref, 0.0);  // control: not black
  const double full_chosen = frame_means(scene, options.field).first;
  std::printf("check at %ux%u: chosen '%s' %.3f (calibration %.3f +- %.3f)\n", kWidth, kHeight,
              choice->chosen.candidate.name.c_str(), full_chosen / full_ref,
              choice->chosen.mean_ratio, choice->chosen.mean_ratio_noise);
  EXPECT_NEAR(full_chosen / full_ref, 1.0, tools::kEnergyBar);
  EXPECT_NEAR(full_chosen / full_ref, choice->chosen.mean_ratio, 0.03);
}

// ddgi-eval --session-defaults end to end: every configuration gets a session's choice over it
// (named in its row, reported on stderr); a configuration that sets a parameter keeps it (its
// candidates do not vary it); the flag with a mode it does not apply to is refused by name.
// Planted: the row keeping its plain name fails it.
TEST(SessionDefaultsEvalCli, GivesEachConfigurationASessionsChoice) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("ddgi-session-eval-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const CliRun run = run_cli(DDGI_EVAL_EXE,
                             "scenes/cornell_box.gltf --width 40 --height 30 --spp 16 --warmup 4 "
                             "--frames 1 --field counts=4,4,4 --session-defaults "
                             "--configs 'own:rays_per_probe=32,pixel_paths=0'",
                             dir);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const std::string said = "own, session default: budget_ms=4 chosen='";
  const size_t chosen_at = run.err.find(said);
  ASSERT_NE(chosen_at, std::string::npos) << run.err;
  const size_t name_at = chosen_at + said.size();
  const std::string chosen = run.err.substr(name_at, run.err.find('\'', name_at) - name_at);
  // Rays, the grid (--field) and paths per pixel fixed: one of the five gatherings.
  bool gathering = false;
  for (const char* name :
       {"static default", "bias 0.5", "paths 1", "paths 1, bias 0.5", "paths 1, gamma 1"}) {
    gathering |= chosen == name;
  }
  EXPECT_TRUE(gathering) << chosen;
  EXPECT_NE(run.err.find("candidates=5 "), std::string::npos) << run.err;
  EXPECT_NE(run.out.find("| cornell_box | own (session: " + chosen + ") |"), std::string::npos)
      << run.out;

  for (const char* mode : {"--budgets 2", "--dynamic light:0:0,0.1,0"}) {
    const CliRun refused = run_cli(
        DDGI_EVAL_EXE, std::string("scenes/cornell_box.gltf --session-defaults ") + mode, dir);
    EXPECT_EQ(refused.exit_code, 2) << mode;
    EXPECT_NE(refused.err.find("--session-defaults applies to the table's configurations"),
              std::string::npos)
        << refused.err;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ddgi::test
