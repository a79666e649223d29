// The energy calibration: candidates, choice and application (tools/field_energy.h).
#include "tools/field_energy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>

#include "gi/param_table.h"

namespace ddgi::tools {

bool sets_energy_params(const std::vector<std::string>& assignments) {
  for (const std::string& a : assignments) {
    const std::string name = a.substr(0, a.find('='));
    for (const char* param : kEnergyParams) {
      if (name == param) return true;
    }
  }
  return false;
}

std::vector<BudgetCandidate> energy_candidates() {
  return {{"static default", {}},
          {"bias 0.5", {"self_shadow_bias=0.5"}},
          {"paths 1", {"probe_bounces=1"}},
          {"paths 1, bias 0.5", {"probe_bounces=1", "self_shadow_bias=0.5"}},
          {"paths 1, gamma 1", {"probe_bounces=1", "irradiance_gamma=1"}},
          {"pixel paths 4x32", {std::begin(kPixelPathsCandidate), std::end(kPixelPathsCandidate)}}};
}

bool traces_pixel_paths(const BudgetCandidate& candidate) {
  // Read through the parameter table, as the calibration applies it: any spelling of a value.
  IrradianceFieldParams params;
  return field_param_table().apply(params, candidate.assignments).ok() && params.pixel_paths > 0;
}

double energy_error(const CalibratedCandidate& c) {
  return std::max(std::abs(c.mean_ratio - 1.0), std::abs(c.indirect_ratio - 1.0));
}

Result<size_t> choose_energy(const Calibration& calibration) {
  const std::vector<CalibratedCandidate>& candidates = calibration.candidates;
  if (candidates.empty()) return invalid_argument("the energy calibration has no candidates");
  // Paths per pixel, noisier than any field, count only where no field candidate meets the bar.
  double least_field = std::numeric_limits<double>::infinity();
  for (const CalibratedCandidate& c : candidates) {
    if (!traces_pixel_paths(c.candidate)) least_field = std::min(least_field, energy_error(c));
  }
  auto counts = [&](size_t i) {
    return least_field > kEnergyAcceptance || !traces_pixel_paths(candidates[i].candidate);
  };
  double least = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (!counts(i)) continue;
    if (energy_error(candidates[i]) <= kEnergyTarget) return i;
    least = std::min(least, energy_error(candidates[i]));
  }
  size_t i = 0;
  while (!counts(i) || energy_error(candidates[i]) > least + kEnergyTie) ++i;
  return i;
}

CalibrationOptions energy_calibration_options() {
  CalibrationOptions options;
  options.width = 320;
  options.height = 180;
  options.timed_frames = 3;
  options.score_indirect = true;
  options.purpose = "energy";
  return options;
}

Result<EnergyChoice> apply_energy(vk::Context& context, const Scene& scene, const Camera& camera,
                                  GiStackOptions& base, const CalibrationOptions& options,
                                  BudgetCache& cache) {
  if (!options.score_indirect) {
    return invalid_argument("an energy calibration scores the field part (score_indirect)");
  }
  EnergyChoice choice;
  const std::vector<BudgetCandidate> candidates = energy_candidates();
  DDGI_ASSIGN_OR_RETURN(
      const Calibration calibration,
      cache.get_or_measure(
          calibration_key(context, scene, base, options) + "|energy",
          [&] { return calibrate(context, scene, camera, base, candidates, options); },
          choice.from_cache));
  DDGI_ASSIGN_OR_RETURN(const size_t index, choose_energy(calibration));
  choice.chosen = calibration.candidates[index];
  choice.static_default = calibration.candidates.front();
  choice.device = calibration.device;
  choice.candidates = calibration.candidates.size();
  choice.calibration_seconds = calibration.seconds;
  DDGI_TRY(field_param_table().apply(base.field, choice.chosen.candidate.assignments));
  return choice;
}

std::string describe(const EnergyChoice& c) {
  char text[400];
  std::snprintf(
      text, sizeof text,
      "chosen='%s' mean/ref=%.3f indirect=%.3f field_ms=%.3f (static default %.3f / "
      "%.3f, %.3f ms) candidates=%zu %s%.1f s",
      c.chosen.candidate.name.c_str(), c.chosen.mean_ratio, c.chosen.indirect_ratio,
      c.chosen.field_ms, c.static_default.mean_ratio, c.static_default.indirect_ratio,
      c.static_default.field_ms, c.candidates,
      c.from_cache ? "calibration=cached, measured in " : "calibration_s=", c.calibration_seconds);
  return text;
}

}  // namespace ddgi::tools
