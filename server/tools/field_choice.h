// The one rule that configures a session (issue 45): of the configurations a calibration measured
// for a scene (tools/field_budget.h), the one of lowest error whose cost fits the session's time
// budget. Never a refusal: where nothing fits, the cheapest is streamed and the report says by
// how much it misses.
//
// The error is the full frame's FLIP against the path tracer, plus the light a candidate gains or
// loses beyond kEnergyBar (as a fraction of the reference's mean, added to FLIP one for one: a
// candidate 8% off counts 0.03 worse). Within the budget, candidates whose light meets the bar
// come first: where any does, the light of the chosen one is within 5%. Every comparison allows
// for noise: a candidate's light meets the bar when it is within kNoiseSigmas standard errors of
// it, and candidates whose errors lie within kNoiseSigmas standard errors of the lowest count as
// equal, the cheapest of them taken. So a decision that noise could flip falls to cost, which is
// measured far more precisely.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/result.h"
#include "tools/field_budget.h"

namespace ddgi::tools {

// The light's bar: a frame's mean within 5% of the path tracer's.
inline constexpr double kEnergyBar = 0.05;
// How many standard errors a measured difference must exceed to count: 2 (about 95% one-sided
// for a normal error; our errors come from 3 scored frames and one reference split in halves).
inline constexpr double kNoiseSigmas = 2.0;

// How far `c`'s light is beyond the bar after its noise: max(0, |mean/ref - 1| - kNoiseSigmas x
// noise - kEnergyBar); 0 for every candidate where the reference is black (nothing to lose).
double energy_excess(const CalibratedCandidate& c, const Calibration& calibration);
// What the rule ranks by: FLIP + energy_excess.
double choice_error(const CalibratedCandidate& c, const Calibration& calibration);

// The time budget of a session that asks for none (ddgi-server --budget-ms): 4 ms of GPU per
// 1920x1080 frame, a 250 fps stream for one session on one GPU, or four views at 60 fps each.
// The measured 1080p frames of the static defaults fit it on an H100 in most scenes (living_room
// 1.4 ms, staircase 3.9 ms with two emitter samples), so it buys accuracy where it is cheap and
// trades it where it is not (paths per pixel at 1080p: 65-150 ms).
inline constexpr double kDefaultBudgetMs = 4.0;

// A session's configuration as the rule chose it, and what the session reports of it.
struct BudgetChoice {
  size_t index = 0;  // into the calibration's candidates
  CalibratedCandidate chosen;
  double budget_ms = 0.0;
  bool budget_met = true;
  double over_ms = 0.0;  // chosen.cost_ms() - budget_ms where not met, else 0
  // The chosen light meets the bar (energy_excess 0), and whether any candidate within the
  // budget does (false: no configuration the budget affords keeps this scene's light).
  bool energy_met = true;
  bool energy_possible = true;
  std::string device;  // the calibration's
  uint32_t width = 0, height = 0;
  size_t candidates = 0;
  double calibration_seconds = 0.0;
  bool from_cache = false;
};

// The rule above. Fails only on a budget out of range or an empty calibration.
Result<BudgetChoice> choose_configuration(const Calibration& calibration, double budget_ms);

// What a tool does to draw what a session draws (ddgi-bench / ddgi-eval --session-defaults):
// calibrates `scene` over `base` (or takes the cached calibration of the same key), chooses by
// the rule for `budget_ms` and applies the choice's assignments to `base.field`. `fixed`: the
// parameters set by hand, which the candidates keep.
Result<BudgetChoice> apply_budget(vk::Context& context, const Scene& scene, const Camera& camera,
                                  GiStackOptions& base, const std::vector<std::string>& fixed,
                                  double budget_ms, const CalibrationOptions& options,
                                  BudgetCache& cache);

// One line for logs and tools: what was chosen, at what cost and error, and what missed.
std::string describe(const BudgetChoice& choice);

}  // namespace ddgi::tools
