// Defaults that do not lose light (issue 14): where the static default field gains or loses
// light against a path tracer, the settings that decide it (how far a probe ray's path is traced
// before it reads the field, the self-shadowing bias, the blend's encoding) are chosen per scene
// from measurements on load, never from a table. Each scene errs its own way: staircase gains
// light through the field's feedback (one traced bounce removes it), modern_hall loses it to
// self-shadowing (a larger bias), box_on_floor's field part to the perceptual blend's
// power-mean (linear blending of traced paths); docs/results/default-energy.md measured each,
// and no one setting passes every scene. The energy calibration scores the candidates'
// full frames and field parts against path-traced references at the session's default view
// (the time budget's machinery, tools/field_budget.h, with score_indirect) and keeps the first
// candidate, in order of cost, within kEnergyTarget; where none is, the one that errs least.
// Light no probe grid holds (cornell_nvpro's albedo-1 slot, cornell_kajiya's lamp-ceiling gap)
// only paths per pixel bring back: the last resort, at their noise.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/result.h"
#include "tools/field_budget.h"

namespace ddgi::tools {

// The field parameters the energy calibration chooses. A session or configuration that sets any
// of them by hand keeps its own (sets_energy_params()).
inline constexpr const char* kEnergyParams[] = {
    "probe_bounces", "self_shadow_bias", "irradiance_gamma", "pixel_paths", "pixel_path_vertices"};
bool sets_energy_params(const std::vector<std::string>& assignments);

// The candidates, cheapest first: the static default (no assignment), a larger self-shadowing
// bias (the same cost), one traced bounce past each probe ray's hit (1.2-2.8x the field update),
// the two together, and one bounce blended linearly; last, the last resort: paths per pixel
// (kPixelPathsCandidate), which bring light no probe grid holds at the noise of a few paths
// per pixel.
std::vector<BudgetCandidate> energy_candidates();
// The last resort's assignments: 4 paths per pixel of up to 32 vertices. cornell_nvpro's
// albedo-1 slot needs the long paths (lavapipe, 160x90: 0.55 with the field at the pixel, 0.61
// with 2 vertices, 0.76 with 8, 0.96 with 32; docs/results/default-energy.md).
inline constexpr const char* kPixelPathsCandidate[] = {"pixel_paths=4", "pixel_path_vertices=32"};
// Whether a candidate traces paths per pixel (sets pixel_paths).
bool traces_pixel_paths(const BudgetCandidate& candidate);

// How far a candidate's light is from the path tracer's: the larger of |full - 1| and
// |indirect - 1| over the mean/ref ratios.
double energy_error(const CalibratedCandidate& candidate);

// A candidate this close in energy_error() is taken as it comes in the cheapest-first order:
// 3%, inside the acceptance's 5% by the spread measured between frame sizes (kajiya, cornell_box:
// 1-2% between 160x90 and 384x216) and a 256-spp reference's noise.
inline constexpr double kEnergyTarget = 0.03;
// Where no candidate is within kEnergyTarget: ones within this of the least error count as equal
// and the cheaper is taken (a reference's noise is about 0.5% of its mean).
inline constexpr double kEnergyTie = 0.005;

// The acceptance's bar (issue 14: every view's mean within 5% of the path tracer's): a
// candidate tracing paths per pixel, noisier than any field, is taken only where no other is
// within it.
inline constexpr double kEnergyAcceptance = 0.05;
// The first candidate within kEnergyTarget, else the cheapest within kEnergyTie of the least
// error; candidates tracing paths per pixel count only where no other is within
// kEnergyAcceptance. A view the path tracer finds black (ratios 0: nothing to lose) errs alike
// in every candidate, so the static default stays.
Result<size_t> choose_energy(const Calibration& calibration);

// How an energy calibration measures: the budget calibration's options with the field part
// scored, a 320x180 frame (the field's light is low-frequency) and no timing beyond 3 frames.
CalibrationOptions energy_calibration_options();

// An energy calibration's outcome, as sessions report it.
struct EnergyChoice {
  CalibratedCandidate chosen;
  CalibratedCandidate static_default;  // the first candidate: what the field would have been
  std::string device;
  size_t candidates = 0;
  double calibration_seconds = 0.0;
  bool from_cache = false;
};

// Calibrates `scene` seen by `camera` over `base` (or takes the cached calibration) and applies
// the chosen candidate's assignments to `base.field`.
Result<EnergyChoice> apply_energy(vk::Context& context, const Scene& scene, const Camera& camera,
                                  GiStackOptions& base, const CalibrationOptions& options,
                                  BudgetCache& cache);

// One log line: what was chosen, its ratios beside the static default's.
std::string describe(const EnergyChoice& choice);

}  // namespace ddgi::tools
