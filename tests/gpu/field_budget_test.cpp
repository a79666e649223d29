// A session's configuration (tools/field_budget.h, tools/field_choice.h): candidates from scene
// analysis and what the session fixed, a calibration that scores every candidate against the
// path tracer with its noise (costs injected: lavapipe's times mean nothing), the choice within a
// budget and the cheapest where nothing fits, the cache, and ddgi-eval --budgets, which checks
// the choice against the measured trade; and the clock warm-up that every timing starts with
// (tools::keep_gpu_busy). The rule on hand-made tables: tests/unit/tools/field_choice_test.cpp.
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

#include "gi/field_params.h"
#include "tests/gpu/cli_run.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"
#include "tools/field_choice.h"
#include "tools/tool_support.h"

namespace ddgi::test {
namespace {

using tools::BudgetCandidate;
using tools::Calibration;

// The Cornell box with a small emissive panel under its ceiling beside the point light.
Scene emitter_lit_box() {
  Scene scene = make_cornell_box();
  const int panel = add_material(scene, glm::vec3(0.0f), glm::vec3(8.0f), "panel");
  add_quad(scene, {-0.8f, 1.95f, -0.8f}, {-0.5f, 1.95f, -0.8f}, {-0.5f, 1.95f, -0.5f},
           {-0.8f, 1.95f, -0.5f}, panel);  // counter-clockwise seen from below: facing down
  return scene;
}

GiStackOptions small_field(vk::Context& context) {
  GiStackOptions options;
  options.backend = context.default_backend();
  options.field.origin = {-0.9f, 0.1f, -0.9f};
  options.field.spacing = {0.6f, 0.6f, 0.6f};
  options.field.counts = {4, 4, 4};
  return options;
}

tools::CalibrationOptions tiny_calibration(size_t candidates) {
  tools::CalibrationOptions options;
  options.width = options.height = 32;
  options.reference_spp = 64;
  options.warmup_updates = 12;
  // Costs unrelated to quality (a permutation of 1..n ms), so that the choice must weigh both.
  for (size_t i = 0; i < candidates; ++i) options.injected_ms.push_back(1.0 + (i * 7) % candidates);
  return options;
}

// What a session may fix to keep a calibration small on lavapipe: the gathering and paths per
// pixel (rays, grid and emitters stay open).
const std::vector<std::string> kFixedGathering = {"probe_bounces=0", "pixel_paths=0"};

class FieldBudgetTest : public GpuTest {};

TEST_F(FieldBudgetTest, CandidatesVaryOnlyWhatTheSceneHasAndTheSessionLeftOpen) {
  const GiStackOptions base = small_field(context());
  const std::vector<BudgetCandidate> lit = tools::budget_candidates(emitter_lit_box(), base.field);
  const std::vector<BudgetCandidate> plain =
      tools::budget_candidates(make_cornell_box(), base.field);
  // Gathering (static, bias, paths 1, both, gamma 1) x rays {32, 64, 128 = base, 256}, emitters
  // {field, sampled} beside the static and one-bounce gathering: 4 x (2 + 1 + 2 + 1 + 1) = 28;
  // the coarse grid at 32 rays x emitters: 2; paths per pixel 1x32 and 4x32: 2.
  EXPECT_EQ(lit.size(), 32u);
  EXPECT_EQ(plain.size(), 23u);  // no emitters: 20 + 1 + 2
  for (const BudgetCandidate& c : plain) {
    EXPECT_EQ(c.name.find("emitters"), std::string::npos) << c.name;
  }
  EXPECT_EQ(lit[0].name, "static default");
  EXPECT_TRUE(lit[0].assignments.empty());
  EXPECT_EQ(lit[1].name, "emitters 2");
  EXPECT_EQ(lit[2].name, "rays 32");
  EXPECT_EQ(lit[3].name, "rays 32, emitters 2");
  EXPECT_EQ(lit[8].name, "bias 0.5");
  EXPECT_EQ(lit[28].name, "rays 32, coarse");
  EXPECT_EQ(lit[31].name, "pixel paths 4x32");
  EXPECT_EQ(lit[31].assignments,
            (std::vector<std::string>{"pixel_paths=4", "pixel_path_vertices=32"}));
  // A base that samples emitters already (an emitter-lit scene's default) is varied the other
  // way, emitter light carried by the field, and with one sample where it takes more.
  IrradianceFieldParams sampled = base.field;
  sampled.emitter_samples = kSceneEmitterSamples;
  const std::vector<BudgetCandidate> flipped = tools::budget_candidates(emitter_lit_box(), sampled);
  ASSERT_EQ(flipped.size(), 41u);  // 4 x (3 + 1 + 3 + 1 + 1) + 3 + 2
  EXPECT_EQ(flipped[1].name, "emitters 1");
  EXPECT_EQ(flipped[1].assignments.back(), "emitter_samples=1");
  EXPECT_EQ(flipped[2].name, "emitters via field");
  EXPECT_EQ(flipped[2].assignments.back(), "emitter_samples=0");
  IrradianceFieldParams coarse = base.field;
  ASSERT_TRUE(field_param_table().apply(coarse, lit[28].assignments).ok());
  EXPECT_EQ(coarse.counts, glm::ivec3(2, 2, 2));
  EXPECT_NEAR(coarse.spacing.x, 1.8f, 1e-5f);
  EXPECT_EQ(coarse.rays_per_probe, 32u);
  // What the session fixed is not varied: rays fixed leaves 5 gatherings, the coarse grid and
  // the pixel paths; the gathering and paths fixed leave rays x emitters and the coarse grid.
  EXPECT_EQ(tools::budget_candidates(make_cornell_box(), base.field, {"rays_per_probe=64"}).size(),
            8u);
  const auto open_rays = tools::budget_candidates(emitter_lit_box(), base.field, kFixedGathering);
  EXPECT_EQ(open_rays.size(), 10u);
  for (const BudgetCandidate& c : open_rays) {
    for (const std::string& a : c.assignments) {
      EXPECT_EQ(a.find("probe_bounces"), std::string::npos) << c.name;
      EXPECT_EQ(a.find("pixel_paths"), std::string::npos) << c.name;
    }
  }
  // A field of cascades keeps its grid (halving one cascade's probes is not a cheaper field of
  // the same reach).
  IrradianceFieldParams cascades = base.field;
  cascades.cascades = 2;
  EXPECT_EQ(tools::budget_candidates(make_cornell_box(), cascades).size(), 22u);
}

TEST_F(FieldBudgetTest, CalibratesWithNoiseAndServesEveryBudget) {
  const Scene scene = emitter_lit_box();
  const GiStackOptions base = small_field(context());
  const std::vector<BudgetCandidate> candidates =
      tools::budget_candidates(scene, base.field, kFixedGathering);
  const tools::CalibrationOptions options = tiny_calibration(candidates.size());
  auto calibrated = tools::calibrate(context(), scene, scene.cameras[0], base, candidates, options);
  ASSERT_TRUE(calibrated.ok()) << calibrated.error().message;
  const Calibration& c = *calibrated;
  ASSERT_EQ(c.candidates.size(), candidates.size());
  EXPECT_GT(c.reference_mean, 0.0);
  // The errors are measured, not trivial: in (0, 1), not all alike, each with a noise above 0
  // and below the error itself.
  double low = 1.0, high = 0.0;
  for (const auto& point : c.candidates) {
    EXPECT_GT(point.flip, 0.0) << point.candidate.name;
    EXPECT_LT(point.flip, 0.5) << point.candidate.name;
    EXPECT_GT(point.flip_noise, 0.0) << point.candidate.name;
    EXPECT_LT(point.flip_noise, point.flip) << point.candidate.name;
    EXPECT_GT(point.mean_ratio, 0.5) << point.candidate.name;
    EXPECT_LT(point.mean_ratio_noise, 0.2) << point.candidate.name;
    low = std::min(low, point.flip);
    high = std::max(high, point.flip);
  }
  EXPECT_GT(high - low, 1e-3) << "FLIP " << low << " .. " << high;
  // Every budget from the cheapest candidate's cost up: a choice that fits it.
  for (double budget = 1.0; budget <= double(candidates.size()); budget += 1.0) {
    auto chosen = tools::choose_configuration(c, budget);
    ASSERT_TRUE(chosen.ok()) << chosen.error().message;
    EXPECT_TRUE(chosen->budget_met);
    EXPECT_LE(chosen->chosen.cost_ms(), budget);
  }
  // Nothing fits: served with the cheapest (injected 1 ms: candidate 0) and its shortfall.
  auto below = tools::choose_configuration(c, 0.5);
  ASSERT_TRUE(below.ok()) << below.error().message;
  EXPECT_FALSE(below->budget_met);
  EXPECT_EQ(below->index, 0u);
  EXPECT_NEAR(below->over_ms, 0.5, 1e-12);
}

// apply_budget: the chosen assignments land in the options; a second load of the same scene is
// served from the cache (same choice, no measuring); a budget nothing fits gets the cheapest.
TEST_F(FieldBudgetTest, ApplyBudgetSetsTheChoiceAndCachesTheCalibration) {
  const Scene scene = make_cornell_box();
  const GiStackOptions base = small_field(context());
  const size_t count = tools::budget_candidates(scene, base.field, kFixedGathering).size();
  const tools::CalibrationOptions options = tiny_calibration(count);
  tools::BudgetCache cache;
  GiStackOptions first = base;
  auto chosen = tools::apply_budget(context(), scene, scene.cameras[0], first, kFixedGathering, 4.0,
                                    options, cache);
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  EXPECT_FALSE(chosen->from_cache);
  EXPECT_EQ(chosen->candidates, count);
  EXPECT_LE(chosen->chosen.cost_ms(), 4.0);
  IrradianceFieldParams expected = base.field;
  ASSERT_TRUE(field_param_table().apply(expected, chosen->chosen.candidate.assignments).ok());
  EXPECT_EQ(first.field.rays_per_probe, expected.rays_per_probe);
  EXPECT_EQ(first.field.counts, expected.counts);

  GiStackOptions second = base;
  auto again = tools::apply_budget(context(), scene, scene.cameras[0], second, kFixedGathering, 4.0,
                                   options, cache);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_TRUE(again->from_cache);
  EXPECT_EQ(again->chosen.candidate.name, chosen->chosen.candidate.name);
  EXPECT_EQ(again->chosen.flip, chosen->chosen.flip);

  GiStackOptions third = base;
  auto cheapest = tools::apply_budget(context(), scene, scene.cameras[0], third, kFixedGathering,
                                      0.5, options, cache);
  ASSERT_TRUE(cheapest.ok()) << cheapest.error().message;
  EXPECT_FALSE(cheapest->budget_met);
  EXPECT_EQ(cheapest->chosen.cost_ms(), 1.0);  // injected: the cheapest
}

// With a directory the cache keeps calibrations on disk: a new cache (a restarted server) on
// the same directory takes the kept one; a damaged file is measured over and rewritten; a
// directory that cannot be made is refused by name.
TEST_F(FieldBudgetTest, CalibrationsKeptOnDiskServeARestartedServer) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("ddgi-budget-cache-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const Scene scene = make_cornell_box();
  const GiStackOptions base = small_field(context());
  const tools::CalibrationOptions options =
      tiny_calibration(tools::budget_candidates(scene, base.field, kFixedGathering).size());
  auto choose = [&](bool expect_cached) {
    tools::BudgetCache cache;  // a server started anew
    EXPECT_TRUE(cache.persist_in(dir.string()).ok());
    GiStackOptions chosen = base;
    auto choice = tools::apply_budget(context(), scene, scene.cameras[0], chosen, kFixedGathering,
                                      4.0, options, cache);
    EXPECT_TRUE(choice.ok()) << choice.error().message;
    if (!choice.ok()) return tools::BudgetChoice{};
    EXPECT_EQ(choice->from_cache, expect_cached);
    return *choice;
  };
  const tools::BudgetChoice first = choose(false);
  tools::BudgetCache names;
  ASSERT_TRUE(names.persist_in(dir.string()).ok());
  const std::string file =
      names.file_of(tools::calibration_key(context(), scene, base, options, kFixedGathering));
  ASSERT_TRUE(std::filesystem::exists(file)) << file;
  const tools::BudgetChoice kept = choose(true);
  EXPECT_EQ(kept.chosen.candidate.name, first.chosen.candidate.name);
  EXPECT_EQ(kept.chosen.flip, first.chosen.flip);
  EXPECT_EQ(kept.candidates, first.candidates);

  std::ofstream(file, std::ios::trunc) << "{\"key\": ";  // damaged
  const tools::BudgetChoice again = choose(false);
  EXPECT_EQ(again.chosen.candidate.name, first.chosen.candidate.name);
  choose(true);  // rewritten whole

  std::ofstream(dir / "plain-file") << "x";
  tools::BudgetCache refused;
  const Status status = refused.persist_in((dir / "plain-file" / "cache").string());
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().message.find("cannot be created or is not a directory"),
            std::string::npos)
      << status.error().message;
  std::filesystem::remove_all(dir);
}

// ddgi-eval --budgets end to end: the table measures the budget's candidates, then a budget
// everything fits picks one of them (its row's measured FLIP is that configuration's in the
// table) and a budget nothing fits streams the cheapest, saying by how much it misses. Planted:
// the chosen row showing another configuration's measurements fails the FLIP check.
TEST(BudgetEvalCli, MeasuresTheCandidatesAndPrintsEachBudgetsChoice) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("ddgi-budget-eval-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const CliRun run = run_cli(DDGI_EVAL_EXE,
                             "scenes/cornell_box.gltf --width 40 --height 30 --spp 16 --warmup 4 "
                             "--frames 1 --field counts=4,4,4 --budgets 1e6,1e-6",
                             dir);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  std::map<std::string, std::string> table_flip;  // configuration -> full-image FLIP
  std::vector<std::vector<std::string>> budget_rows;
  std::istringstream lines(run.out);
  for (std::string line; std::getline(lines, line);) {
    const std::vector<std::string> cells = markdown_cells(line);
    if (cells.size() == 13 && cells[0] == "cornell_box") table_flip[cells[1]] = cells[5];
    if (cells.size() == 9 && cells[0] == "cornell_box") budget_rows.push_back(cells);
  }
  // 5 gatherings x rays {32, 64, 128, 256}, the coarse grid, 2 pixel-path settings: no emissive
  // surface in the box.
  EXPECT_EQ(table_flip.size(), 23u) << run.out;
  EXPECT_TRUE(table_flip.count("rays 32, coarse")) << run.out;
  ASSERT_EQ(budget_rows.size(), 2u) << run.out;
  const std::vector<std::string>& fits = budget_rows[0];
  EXPECT_EQ(fits[1], "1e+06");
  ASSERT_TRUE(table_flip.count(fits[2])) << "chosen '" << fits[2] << "'\n" << run.out;
  EXPECT_DOUBLE_EQ(std::stod(fits[6]), std::stod(table_flip[fits[2]])) << run.out;
  EXPECT_GT(std::stod(fits[3]), 0.0);  // calibrated ms
  EXPECT_GT(std::stod(fits[4]), 0.0);  // measured ms
  EXPECT_GE(std::stod(fits[8]), 1.0);  // FLIP over the best within the budget: all fit
  EXPECT_NE(budget_rows[1][2].find(", the cheapest: budget not met by "), std::string::npos)
      << run.out;
  ASSERT_TRUE(
      table_flip.count(budget_rows[1][2].substr(0, budget_rows[1][2].find(", the cheapest"))))
      << budget_rows[1][2];
  // The calibration's own figures, one line per candidate on stderr: what the choice was made on.
  for (const auto& entry : table_flip) {
    const std::string& name = entry.first;
    const std::string line = "  " + name + ": ";
    const size_t at = run.err.find(line);
    ASSERT_NE(at, std::string::npos) << name << "\n" << run.err;
    const std::string rest = run.err.substr(at + line.size(), run.err.find('\n', at) - at);
    const size_t flip_at = rest.find(" ms, FLIP ");
    ASSERT_NE(flip_at, std::string::npos) << rest;
    EXPECT_GT(std::stod(rest.substr(0, flip_at)), 0.0) << rest;
    EXPECT_GT(std::stod(rest.substr(flip_at + 10)), 0.0) << rest;
  }

  const CliRun bad = run_cli(DDGI_EVAL_EXE, "scenes/cornell_box.gltf --budgets 2,0", dir);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("budget_ms must be in (0, 1e+06]"), std::string::npos) << bad.err;
  const CliRun both =
      run_cli(DDGI_EVAL_EXE, "scenes/cornell_box.gltf --budgets 2 --configs a:", dir);
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("drop --configs"), std::string::npos) << both.err;
  std::filesystem::remove_all(dir);
}

// The clock warm-up before timing: work repeated until the duration has passed, at least once,
// and stopped at the first error.
TEST(KeepGpuBusy, RepeatsTheWorkForTheDurationAndStopsAtAnError) {
  int calls = 0;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(tools::keep_gpu_busy(std::chrono::milliseconds(50), [&]() -> Status {
                ++calls;
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                return ok_status();
              }).ok());
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(50));
  EXPECT_GE(calls, 5) << "5 ms per call over 50 ms";
  calls = 0;
  EXPECT_TRUE(tools::keep_gpu_busy(std::chrono::milliseconds(0), [&]() -> Status {
                ++calls;
                return ok_status();
              }).ok());
  EXPECT_EQ(calls, 1) << "at least once";
  calls = 0;
  const Status failed = tools::keep_gpu_busy(std::chrono::milliseconds(1000), [&]() -> Status {
    ++calls;
    return internal_error("device lost");
  });
  EXPECT_FALSE(failed.ok());
  EXPECT_EQ(calls, 1) << "stopped at the error";
}

}  // namespace
}  // namespace ddgi::test
