// The time budget (tools/field_budget.h): candidates from scene analysis, a calibration that
// scores every candidate against the path tracer (costs injected: lavapipe's times mean nothing),
// the choice of the lowest error that fits, the refusal of a budget nothing fits, the cache, and
// ddgi-eval --budgets, which checks the choice against the measured trade; and the clock
// warm-up that every timing starts with (tools::keep_gpu_busy).
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
#include "tools/field_budget.h"
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

// The index a correct choice gives: the lowest FLIP among the candidates within the budget.
std::optional<size_t> best_within(const Calibration& c, double budget_ms) {
  std::optional<size_t> best;
  for (size_t i = 0; i < c.candidates.size(); ++i) {
    if (c.candidates[i].cost_ms() > budget_ms) continue;
    if (!best || c.candidates[i].flip < c.candidates[*best].flip) best = i;
  }
  return best;
}

class FieldBudgetTest : public GpuTest {};

TEST_F(FieldBudgetTest, CandidatesVaryOnlyWhatTheSceneHas) {
  const GiStackOptions base = small_field(context());
  const std::vector<BudgetCandidate> lit = tools::budget_candidates(emitter_lit_box(), base.field);
  const std::vector<BudgetCandidate> plain =
      tools::budget_candidates(make_cornell_box(), base.field);
  // Rays 32..256 x {grid, coarse} x {no emitter sampling, emitters 2}; no emitters: half.
  EXPECT_EQ(lit.size(), 16u);
  EXPECT_EQ(plain.size(), 8u);
  for (const BudgetCandidate& c : plain) {
    EXPECT_EQ(c.name.find("emitters"), std::string::npos) << c.name;
  }
  // The coarse grid keeps the extent: 4 probes 0.6 apart -> 2 probes 1.8 apart.
  EXPECT_EQ(lit[1].name, "rays 32, emitters 2");
  EXPECT_EQ(lit[2].name, "rays 32, coarse");
  // A base that samples emitters already (an emitter-lit scene's default) is varied the other
  // way, emitter light carried by the field, and with one sample where it takes more.
  IrradianceFieldParams sampled = base.field;
  sampled.emitter_samples = kSceneEmitterSamples;
  const std::vector<BudgetCandidate> flipped = tools::budget_candidates(emitter_lit_box(), sampled);
  ASSERT_EQ(flipped.size(), 24u);
  EXPECT_EQ(flipped[1].name, "rays 32, emitters 1");
  EXPECT_EQ(flipped[1].assignments.back(), "emitter_samples=1");
  EXPECT_EQ(flipped[2].name, "rays 32, emitters via field");
  EXPECT_EQ(flipped[2].assignments.back(), "emitter_samples=0");
  EXPECT_EQ(flipped[3].name, "rays 32, coarse");
  sampled.emitter_samples = 1;
  const std::vector<BudgetCandidate> single = tools::budget_candidates(emitter_lit_box(), sampled);
  ASSERT_EQ(single.size(), 16u);
  EXPECT_EQ(single[1].name, "rays 32, emitters via field");
  IrradianceFieldParams coarse = base.field;
  ASSERT_TRUE(field_param_table().apply(coarse, lit[2].assignments).ok());
  EXPECT_EQ(coarse.counts, glm::ivec3(2, 2, 2));
  EXPECT_NEAR(coarse.spacing.x, 1.8f, 1e-5f);
  // A field of cascades keeps its grid (halving one cascade's probes is not a cheaper field of
  // the same reach).
  IrradianceFieldParams cascades = base.field;
  cascades.cascades = 2;
  EXPECT_EQ(tools::budget_candidates(make_cornell_box(), cascades).size(), 4u);
}

TEST_F(FieldBudgetTest, PicksTheLowestErrorThatFitsAndRefusesAnImpossibleBudget) {
  const Scene scene = emitter_lit_box();
  const GiStackOptions base = small_field(context());
  const std::vector<BudgetCandidate> candidates = tools::budget_candidates(scene, base.field);
  const tools::CalibrationOptions options = tiny_calibration(candidates.size());
  auto calibrated = tools::calibrate(context(), scene, scene.cameras[0], base, candidates, options);
  ASSERT_TRUE(calibrated.ok()) << calibrated.error().message;
  const Calibration& c = *calibrated;
  ASSERT_EQ(c.candidates.size(), candidates.size());
  // The errors are measured, not trivial: in (0, 1) and not all alike.
  double low = 1.0, high = 0.0;
  for (const auto& point : c.candidates) {
    EXPECT_GT(point.flip, 0.0) << point.candidate.name;
    EXPECT_LT(point.flip, 0.5) << point.candidate.name;
    low = std::min(low, point.flip);
    high = std::max(high, point.flip);
  }
  EXPECT_GT(high - low, 1e-3) << "FLIP " << low << " .. " << high;
  // Every budget from the cheapest candidate's cost up: the lowest error within it.
  for (double budget = 1.0; budget <= double(candidates.size()); budget += 1.0) {
    auto chosen = tools::choose_within_budget(c, budget);
    ASSERT_TRUE(chosen.ok()) << chosen.error().message;
    EXPECT_EQ(*chosen, best_within(c, budget).value()) << "budget " << budget;
    EXPECT_LE(c.candidates[*chosen].cost_ms(), budget);
  }
  // Nothing fits: refused, naming the cheapest candidate (injected 1 ms: candidate 0).
  auto impossible = tools::choose_within_budget(c, 0.5);
  ASSERT_FALSE(impossible.ok());
  EXPECT_EQ(impossible.error().code, ErrorCode::kFailedPrecondition);
  EXPECT_NE(impossible.error().message.find("budget_ms 0.5 cannot be met"), std::string::npos)
      << impossible.error().message;
  EXPECT_NE(impossible.error().message.find("'rays 32', costs 1.000 ms"), std::string::npos)
      << impossible.error().message;
  for (const double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), 2e6}) {
    auto refused = tools::choose_within_budget(c, bad);
    ASSERT_FALSE(refused.ok()) << bad;
    EXPECT_NE(refused.error().message.find("budget_ms must be in (0, 1e+06]"), std::string::npos)
        << refused.error().message;
  }
}

// apply_budget: the chosen assignments land in the options; a second load of the same scene is
// served from the cache (same choice, no measuring); an impossible budget changes nothing.
TEST_F(FieldBudgetTest, ApplyBudgetSetsTheChoiceAndCachesTheCalibration) {
  const Scene scene = make_cornell_box();
  const GiStackOptions base = small_field(context());
  const size_t count = tools::budget_candidates(scene, base.field).size();
  const tools::CalibrationOptions options = tiny_calibration(count);
  tools::BudgetCache cache;
  GiStackOptions first = base;
  auto chosen = tools::apply_budget(context(), scene, scene.cameras[0], first, 4.0, options, cache);
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  EXPECT_FALSE(chosen->from_cache);
  EXPECT_EQ(chosen->candidates, count);
  EXPECT_LE(chosen->chosen.cost_ms(), 4.0);
  IrradianceFieldParams expected = base.field;
  ASSERT_TRUE(field_param_table().apply(expected, chosen->chosen.candidate.assignments).ok());
  EXPECT_EQ(first.field.rays_per_probe, expected.rays_per_probe);
  EXPECT_EQ(first.field.counts, expected.counts);

  GiStackOptions second = base;
  auto again = tools::apply_budget(context(), scene, scene.cameras[0], second, 4.0, options, cache);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_TRUE(again->from_cache);
  EXPECT_EQ(again->chosen.candidate.name, chosen->chosen.candidate.name);
  EXPECT_EQ(again->chosen.flip, chosen->chosen.flip);

  GiStackOptions third = base;
  auto refused =
      tools::apply_budget(context(), scene, scene.cameras[0], third, 0.5, options, cache);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(third.field.rays_per_probe, base.field.rays_per_probe);
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
      tiny_calibration(tools::budget_candidates(scene, base.field).size());
  auto choose = [&](bool expect_cached) {
    tools::BudgetCache cache;  // a server started anew
    EXPECT_TRUE(cache.persist_in(dir.string()).ok());
    GiStackOptions chosen = base;
    auto choice =
        tools::apply_budget(context(), scene, scene.cameras[0], chosen, 4.0, options, cache);
    EXPECT_TRUE(choice.ok()) << choice.error().message;
    if (!choice.ok()) return tools::BudgetChoice{};
    EXPECT_EQ(choice->from_cache, expect_cached);
    return *choice;
  };
  const tools::BudgetChoice first = choose(false);
  tools::BudgetCache names;
  ASSERT_TRUE(names.persist_in(dir.string()).ok());
  const std::string file = names.file_of(tools::calibration_key(context(), scene, base, options));
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
// table) and a budget nothing fits is refused by name. Planted: the chosen row showing another
// configuration's measurements fails the FLIP check.
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
  // Rays 32..256 x {4x4x4, 2x2x2}: no emissive surface in the box.
  EXPECT_EQ(table_flip.size(), 8u) << run.out;
  EXPECT_TRUE(table_flip.count("rays 128, coarse")) << run.out;
  ASSERT_EQ(budget_rows.size(), 2u) << run.out;
  const std::vector<std::string>& fits = budget_rows[0];
  EXPECT_EQ(fits[1], "1e+06");
  ASSERT_TRUE(table_flip.count(fits[2])) << "chosen '" << fits[2] << "'\n" << run.out;
  EXPECT_DOUBLE_EQ(std::stod(fits[6]), std::stod(table_flip[fits[2]])) << run.out;
  EXPECT_GT(std::stod(fits[3]), 0.0);  // calibrated ms
  EXPECT_GT(std::stod(fits[4]), 0.0);  // measured ms
  EXPECT_GE(std::stod(fits[8]), 1.0);  // FLIP over the best within the budget: all fit
  EXPECT_NE(budget_rows[1][2].find("refused: budget_ms 1e-06 cannot be met"), std::string::npos)
      << run.out;
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
