// The budget_ms field parameter and the reports of a session's configuration
// (service/session_budget.h).
#include "service/session_budget.h"

#include <cstdio>
#include <sstream>

#include "core/flags.h"

namespace ddgi::service {

Status check_calibration_share(double share) {
  if (share > 0.0 && share <= 1.0) return ok_status();
  std::ostringstream text;
  text << "--calibration-share must be in (0, 1] (got " << share << ")";
  return invalid_argument(text.str());
}

Result<std::optional<double>> take_budget(std::vector<std::string>& assignments) {
  const std::string prefix = std::string(kBudgetParam) + "=";
  std::optional<double> budget;
  std::vector<std::string> rest;
  for (std::string& assignment : assignments) {
    if (assignment.rfind(prefix, 0) != 0) {
      rest.push_back(std::move(assignment));
      continue;
    }
    const std::string text = assignment.substr(prefix.size());
    const Result<double> value = parse_double(text, kBudgetParam);
    if (!value.ok()) {
      return invalid_argument(std::string(kBudgetParam) + " '" + text +
                              "' is not a number of milliseconds");
    }
    if (*value != 0.0) DDGI_TRY(tools::check_budget_ms(*value));
    budget = *value;
  }
  assignments = std::move(rest);
  return budget;
}

namespace {

template <typename Message>
void add_assignments(const std::vector<std::string>& assignments, Message* out) {
  for (const std::string& assignment : assignments) {
    const size_t eq = assignment.find('=');
    auto* param = out->add_params();
    param->set_name(assignment.substr(0, eq));
    param->set_value(eq == std::string::npos ? "" : assignment.substr(eq + 1));
  }
}

// The report's line for people: what is not met, if anything.
std::string note_of(const tools::BudgetChoice& choice, const std::string& scene_label) {
  char text[256];
  std::string note;
  if (!choice.budget_met) {
    std::snprintf(text, sizeof text,
                  "budget not met by %.2f ms: streaming the cheapest configuration measured",
                  choice.over_ms);
    note = text;
  }
  if (!choice.energy_possible) {
    note += (note.empty() ? "" : "; ") + std::string("no configuration within the budget keeps ") +
            scene_label + "'s light within 5% of the path tracer's";
  } else if (!choice.energy_met) {
    note += (note.empty() ? "" : "; ") + std::string("its light is beyond 5% of the path tracer's");
  }
  return note;
}

}  // namespace

void to_proto(const tools::BudgetChoice& choice, const std::string& scene_label,
              v1::FieldBudget* out) {
  const tools::CalibratedCandidate& c = choice.chosen;
  out->set_budget_ms(choice.budget_ms);
  out->set_configuration(c.candidate.name);
  add_assignments(c.candidate.assignments, out);
  out->set_cost_ms(c.cost_ms());
  out->set_shadow_ms(c.shadow_ms);
  out->set_field_ms(c.field_ms);
  out->set_frame_ms(c.frame_ms);
  out->set_flip(c.flip);
  out->set_flip_noise(c.flip_noise);
  out->set_mean_ratio(c.mean_ratio);
  out->set_mean_ratio_noise(c.mean_ratio_noise);
  out->set_width(choice.width);
  out->set_height(choice.height);
  out->set_device(choice.device);
  out->set_candidates(static_cast<uint32_t>(choice.candidates));
  out->set_calibration_seconds(choice.calibration_seconds);
  out->set_from_cache(choice.from_cache);
  out->set_budget_met(choice.budget_met);
  out->set_over_ms(choice.over_ms);
  out->set_energy_met(choice.energy_met);
  out->set_energy_possible(choice.energy_possible);
  out->set_note(note_of(choice, scene_label));
}

}  // namespace ddgi::service
