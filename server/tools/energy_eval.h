// ddgi-eval --energy: each configuration of the table that sets none of the energy parameters
// (tools/field_energy.h) gets the energy calibration's choice first, as a ddgi-server session
// does (--energy-calibration), so that the table scores what a session would draw. The choice
// and the calibration's own ratios go to stderr; the row's name says what was chosen.
#pragma once

#include <vector>

#include "core/result.h"
#include "scene/scene.h"
#include "tools/eval_job.h"
#include "vk/context.h"

namespace ddgi::tools {

Result<std::vector<Config>> energy_configs(vk::Context& context, const EvalJob& job,
                                           const Scene& scene, const Camera& camera,
                                           const std::vector<Config>& configs);

}  // namespace ddgi::tools
