// The rule that configures a session (tools/field_choice.h).
#include "tools/field_choice.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "gi/field_params.h"
#include "gi/param_table.h"

namespace ddgi::tools {
namespace {

// The cheapest of `pool` (ties: the lower error).
size_t cheapest(const Calibration& calibration, const std::vector<size_t>& pool) {
  size_t best = pool.front();
  for (const size_t i : pool) {
    const CalibratedCandidate& c = calibration.candidates[i];
    const CalibratedCandidate& b = calibration.candidates[best];
    if (c.cost_ms() < b.cost_ms() ||
        (c.cost_ms() == b.cost_ms() &&
         choice_error(c, calibration) < choice_error(b, calibration))) {
      best = i;
    }
  }
  return best;
}

// The lowest error of `pool`, then the cheapest of those within the noise of it.
size_t lowest_error(const Calibration& calibration, const std::vector<size_t>& pool) {
  const auto& all = calibration.candidates;
  size_t best = pool.front();
  for (const size_t i : pool) {
    if (choice_error(all[i], calibration) < choice_error(all[best], calibration)) best = i;
  }
  const double best_error = choice_error(all[best], calibration);
  std::vector<size_t> tied;
  for (const size_t i : pool) {
    const double noise = std::hypot(all[i].flip_noise, all[best].flip_noise);
    if (choice_error(all[i], calibration) <= best_error + kNoiseSigmas * noise) tied.push_back(i);
  }
  return cheapest(calibration, tied);
}

}  // namespace

double energy_excess(const CalibratedCandidate& c, const Calibration& calibration) {
  if (calibration.reference_mean <= 0.0) return 0.0;
  const double off = std::abs(c.mean_ratio - 1.0) - kNoiseSigmas * c.mean_ratio_noise;
  return std::max(0.0, off - kEnergyBar);
}

double choice_error(const CalibratedCandidate& c, const Calibration& calibration) {
  return c.flip + energy_excess(c, calibration);
}

Result<BudgetChoice> choose_configuration(const Calibration& calibration, double budget_ms) {
  DDGI_TRY(check_budget_ms(budget_ms));
  const std::vector<CalibratedCandidate>& all = calibration.candidates;
  if (all.empty()) return invalid_argument("the calibration has no candidates");
  std::vector<size_t> within, keeps_light, every;
  for (size_t i = 0; i < all.size(); ++i) {
    every.push_back(i);
    if (all[i].cost_ms() > budget_ms) continue;
    within.push_back(i);
    if (energy_excess(all[i], calibration) == 0.0) keeps_light.push_back(i);
  }
  BudgetChoice choice;
  if (within.empty()) {
    choice.index = cheapest(calibration, every);
  } else {
    choice.index = lowest_error(calibration, keeps_light.empty() ? within : keeps_light);
  }
  choice.chosen = all[choice.index];
  choice.budget_ms = budget_ms;
  choice.budget_met = !within.empty();
  choice.over_ms = choice.budget_met ? 0.0 : choice.chosen.cost_ms() - budget_ms;
  choice.energy_met = energy_excess(choice.chosen, calibration) == 0.0;
  choice.energy_possible = !keeps_light.empty() || (within.empty() && choice.energy_met);
  choice.device = calibration.device;
  choice.width = calibration.width;
  choice.height = calibration.height;
  choice.candidates = all.size();
  choice.calibration_seconds = calibration.seconds;
  return choice;
}

Result<BudgetChoice> apply_budget(vk::Context& context, const Scene& scene, const Camera& camera,
                                  GiStackOptions& base, const std::vector<std::string>& fixed,
                                  double budget_ms, const CalibrationOptions& options,
                                  BudgetCache& cache) {
  DDGI_TRY(check_budget_ms(budget_ms));  // before seconds of calibration, not after
  const std::vector<BudgetCandidate> candidates = budget_candidates(scene, base.field, fixed);
  bool from_cache = false;
  DDGI_ASSIGN_OR_RETURN(
      const Calibration calibration,
      cache.get_or_measure(
          calibration_key(context, scene, base, options, fixed),
          [&] { return calibrate(context, scene, camera, base, candidates, options); },
          from_cache));
  DDGI_ASSIGN_OR_RETURN(BudgetChoice choice, choose_configuration(calibration, budget_ms));
  choice.from_cache = from_cache;
  DDGI_TRY(field_param_table().apply(base.field, choice.chosen.candidate.assignments));
  return choice;
}

std::string describe(const BudgetChoice& c) {
  char over[64];
  std::snprintf(over, sizeof over, " BUDGET NOT MET by %.3f ms", c.over_ms);
  char text[512];
  std::snprintf(
      text, sizeof text,
      "budget_ms=%g chosen='%s' cost_ms=%.3f (shadow %.3f + field %.3f + frame %.3f at "
      "%ux%u) flip=%.4f+-%.4f mean/ref=%.3f+-%.3f%s%s candidates=%zu %s%.1f s",
      c.budget_ms, c.chosen.candidate.name.c_str(), c.chosen.cost_ms(), c.chosen.shadow_ms,
      c.chosen.field_ms, c.chosen.frame_ms, c.width, c.height, c.chosen.flip, c.chosen.flip_noise,
      c.chosen.mean_ratio, c.chosen.mean_ratio_noise, c.budget_met ? "" : over,
      c.energy_met ? "" : " (light beyond 5% of the path tracer's)", c.candidates,
      c.from_cache ? "calibration=cached, measured in " : "calibration_s=", c.calibration_seconds);
  return text;
}

}  // namespace ddgi::tools
