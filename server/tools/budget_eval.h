// ddgi-eval --budgets: checks the time budget's choice (tools/field_budget.h) against the
// measured trade. The table's configurations are the budget's own candidates for each scene,
// measured as ddgi-eval measures (cost at --width x --height over --frames, error against the
// --spp reference); then the server's calibration runs as a session would and, per budget,
// its choice is compared with what was measured: the chosen configuration's measured cost over
// the budget (the goal: at most 1.1) and its FLIP over the best measured configuration that
// fits the budget (the goal: at most 1.1).
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"
#include "tools/eval_job.h"
#include "tools/pareto.h"
#include "vk/context.h"

namespace ddgi::tools {

// The budget's candidates for `scene` over its fitted field with --field's assignments.
Result<std::vector<Config>> budget_configs(vk::Context& context, const EvalJob& job,
                                           const Scene& scene);

// The budget table's rows for one scene: `measured` holds the evaluated budget_configs(), in
// their order.
Result<std::vector<std::string>> budget_rows(vk::Context& context, const EvalJob& job,
                                             const Scene& scene, const std::string& stem,
                                             const std::vector<ConfigPoint>& measured);

// The header and `rows`.
void print_budget_table(const std::vector<std::string>& rows);

}  // namespace ddgi::tools
