// ddgi-eval --session-defaults: each configuration of the table gets the configuration a
// ddgi-server session would choose (tools/field_choice.h) over it, at the server's default budget
// (kDefaultBudgetMs) and the job's frame size, so that the table scores what a session draws. The
// parameters a configuration sets stay its own (the candidates do not vary them). The choice goes
// to stderr; the row's name says what was chosen.
#pragma once

#include <vector>

#include "core/result.h"
#include "scene/scene.h"
#include "tools/eval_job.h"
#include "vk/context.h"

namespace ddgi::tools {

Result<std::vector<Config>> session_default_configs(vk::Context& context, const EvalJob& job,
                                                    const Scene& scene, const Camera& camera,
                                                    const std::vector<Config>& configs);

}  // namespace ddgi::tools
