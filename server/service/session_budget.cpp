// The budget_ms field parameter and its report (service/session_budget.h).
#include "service/session_budget.h"

#include "core/flags.h"

namespace ddgi::service {

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

}  // namespace

void to_proto(const tools::BudgetChoice& choice, v1::FieldBudget* out) {
  const tools::CalibratedCandidate& c = choice.chosen;
  out->set_budget_ms(choice.budget_ms);
  out->set_configuration(c.candidate.name);
  add_assignments(c.candidate.assignments, out);
  out->set_cost_ms(c.cost_ms());
  out->set_field_ms(c.field_ms);
  out->set_frame_ms(c.frame_ms);
  out->set_flip(c.flip);
  out->set_mean_ratio(c.mean_ratio);
  out->set_width(choice.width);
  out->set_height(choice.height);
  out->set_device(choice.device);
  out->set_candidates(static_cast<uint32_t>(choice.candidates));
  out->set_calibration_seconds(choice.calibration_seconds);
  out->set_from_cache(choice.from_cache);
}

void to_proto(const tools::EnergyChoice& choice, v1::FieldEnergy* out) {
  const tools::CalibratedCandidate& c = choice.chosen;
  out->set_configuration(c.candidate.name);
  add_assignments(c.candidate.assignments, out);
  out->set_mean_ratio(c.mean_ratio);
  out->set_indirect_ratio(c.indirect_ratio);
  out->set_flip(c.flip);
  out->set_field_ms(c.field_ms);
  out->set_default_mean_ratio(choice.static_default.mean_ratio);
  out->set_default_indirect_ratio(choice.static_default.indirect_ratio);
  out->set_default_field_ms(choice.static_default.field_ms);
  out->set_device(choice.device);
  out->set_candidates(static_cast<uint32_t>(choice.candidates));
  out->set_calibration_seconds(choice.calibration_seconds);
  out->set_from_cache(choice.from_cache);
}

}  // namespace ddgi::service
