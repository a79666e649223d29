// ddgi-eval --budgets (tools/budget_eval.h).
#include "tools/budget_eval.h"

#include <cstdio>
#include <optional>

#include "gi/gi_stack.h"
#include "gpu_scene/camera_fit.h"
#include "tools/field_choice.h"

namespace ddgi::tools {
namespace {

// The session's field for `scene`: fitted, with --field's assignments.
Result<GiStackOptions> base_options(vk::Context& context, const EvalJob& job, const Scene& scene) {
  return fitted_gi_options(scene, true, DirectMode::kTracedShadows, job.field_assignments, {},
                           context.default_backend());
}

// The measured configuration of lowest FLIP whose measured cost fits `budget_ms`.
std::optional<size_t> best_measured(const std::vector<ConfigPoint>& measured, double budget_ms) {
  std::optional<size_t> best;
  for (size_t i = 0; i < measured.size(); ++i) {
    if (measured[i].total_ms() > budget_ms) continue;
    if (!best || measured[i].full.flip < measured[*best].full.flip) best = i;
  }
  return best;
}

std::string row(const std::string& stem, const BudgetChoice& choice,
                const std::vector<ConfigPoint>& measured) {
  char text[512];
  const std::optional<size_t> best = best_measured(measured, choice.budget_ms);
  const std::string best_text = best ? measured[*best].name + " (" +
                                           std::to_string(measured[*best].full.flip).substr(0, 6) +
                                           ")"
                                     : "none fits";
  const CalibratedCandidate& c = choice.chosen;
  const ConfigPoint& m = measured[choice.index];
  const std::string chosen =
      c.candidate.name + (choice.budget_met ? ""
                                            : ", the cheapest: budget not met by " +
                                                  std::to_string(choice.over_ms) + " ms");
  const std::string flip_ratio =
      best ? std::to_string(m.full.flip / measured[*best].full.flip).substr(0, 5) : "-";
  std::snprintf(text, sizeof text, "| %s | %g | %s | %.3f | %.3f | %.2f | %.4f | %s | %s |",
                stem.c_str(), choice.budget_ms, chosen.c_str(), c.cost_ms(), m.total_ms(),
                m.total_ms() / choice.budget_ms, m.full.flip, best_text.c_str(),
                flip_ratio.c_str());
  return text;
}

}  // namespace

Result<std::vector<Config>> budget_configs(vk::Context& context, const EvalJob& job,
                                           const Scene& scene) {
  DDGI_ASSIGN_OR_RETURN(const GiStackOptions base, base_options(context, job, scene));
  std::vector<Config> configs;
  for (const BudgetCandidate& c : budget_candidates(scene, base.field)) {
    configs.push_back({c.name, c.assignments});
  }
  return configs;
}

Result<std::vector<std::string>> budget_rows(vk::Context& context, const EvalJob& job,
                                             const Scene& scene, const std::string& stem,
                                             const std::vector<ConfigPoint>& measured) {
  DDGI_ASSIGN_OR_RETURN(const GiStackOptions base, base_options(context, job, scene));
  const std::vector<BudgetCandidate> candidates = budget_candidates(scene, base.field);
  if (candidates.size() != measured.size()) {
    return internal_error("the budget's candidates changed between the table and calibration");
  }
  CalibrationOptions options;
  options.width = job.width;
  options.height = job.height;
  std::fprintf(stderr, "%s: calibrating %zu candidates as a session would\n", stem.c_str(),
               candidates.size());
  DDGI_ASSIGN_OR_RETURN(
      const Calibration calibration,
      calibrate(context, scene, default_camera(scene), base, candidates, options));
  std::fprintf(stderr, "%s: calibrated in %.1f s\n", stem.c_str(), calibration.seconds);
  for (const CalibratedCandidate& c : calibration.candidates) {
    std::fprintf(stderr, "  %s: %.3f ms, FLIP %.4f +- %.4f, mean/ref %.3f +- %.3f\n",
                 c.candidate.name.c_str(), c.cost_ms(), c.flip, c.flip_noise, c.mean_ratio,
                 c.mean_ratio_noise);
  }
  std::vector<std::string> rows;
  for (const double budget_ms : job.budgets) {
    DDGI_ASSIGN_OR_RETURN(const BudgetChoice choice, choose_configuration(calibration, budget_ms));
    rows.push_back(row(stem, choice, measured));
  }
  return rows;
}

void print_budget_table(const std::vector<std::string>& rows) {
  std::printf(
      "\n| scene | budget ms | chosen | calibrated ms | measured ms | measured / budget | FLIP | "
      "best measured within budget (FLIP) | FLIP / best |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& r : rows) std::printf("%s\n", r.c_str());
}

}  // namespace ddgi::tools
