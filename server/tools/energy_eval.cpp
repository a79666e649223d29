// ddgi-eval --energy (tools/energy_eval.h).
#include "tools/energy_eval.h"

#include <cstdio>

#include "gi/gi_stack.h"
#include "tools/field_energy.h"

namespace ddgi::tools {

Result<std::vector<Config>> energy_configs(vk::Context& context, const EvalJob& job,
                                           const Scene& scene, const Camera& camera,
                                           const std::vector<Config>& configs) {
  std::vector<Config> out;
  BudgetCache cache;  // configurations alike in their base calibrate once
  for (Config config : configs) {
    const std::vector<std::string> assignments = config_assignments(job, config);
    if (sets_energy_params(assignments)) {
      out.push_back(std::move(config));
      continue;
    }
    DDGI_ASSIGN_OR_RETURN(GiStackOptions base,
                          fitted_gi_options(scene, true, config.direct_mode, assignments,
                                            config.shadow_assignments, context.default_backend()));
    DDGI_ASSIGN_OR_RETURN(
        const EnergyChoice choice,
        apply_energy(context, scene, camera, base, energy_calibration_options(), cache));
    std::fprintf(stderr, "%s, energy: %s\n", config.name.c_str(), describe(choice).c_str());
    const std::vector<std::string>& chosen = choice.chosen.candidate.assignments;
    config.assignments.insert(config.assignments.end(), chosen.begin(), chosen.end());
    config.name += " (energy: " + choice.chosen.candidate.name + ")";
    out.push_back(std::move(config));
  }
  return out;
}

}  // namespace ddgi::tools
