// ddgi-eval --session-defaults (tools/session_defaults_eval.h).
#include "tools/session_defaults_eval.h"

#include <cstdio>

#include "gi/gi_stack.h"
#include "tools/field_choice.h"

namespace ddgi::tools {

Result<std::vector<Config>> session_default_configs(vk::Context& context, const EvalJob& job,
                                                    const Scene& scene, const Camera& camera,
                                                    const std::vector<Config>& configs) {
  std::vector<Config> out;
  BudgetCache cache;  // configurations alike in their base calibrate once
  CalibrationOptions options;
  options.width = job.width;
  options.height = job.height;
  options.purpose = "session";
  for (Config config : configs) {
    const std::vector<std::string> assignments = config_assignments(job, config);
    DDGI_ASSIGN_OR_RETURN(GiStackOptions base,
                          fitted_gi_options(scene, true, config.direct_mode, assignments,
                                            config.shadow_assignments, context.default_backend()));
    DDGI_ASSIGN_OR_RETURN(
        const BudgetChoice choice,
        apply_budget(context, scene, camera, base, assignments, kDefaultBudgetMs, options, cache));
    std::fprintf(stderr, "%s, session default: %s\n", config.name.c_str(),
                 describe(choice).c_str());
    const std::vector<std::string>& chosen = choice.chosen.candidate.assignments;
    config.assignments.insert(config.assignments.end(), chosen.begin(), chosen.end());
    config.name += " (session: " + choice.chosen.candidate.name + ")";
    out.push_back(std::move(config));
  }
  return out;
}

}  // namespace ddgi::tools
