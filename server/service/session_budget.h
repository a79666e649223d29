// The time budget as the service offers it: the `budget_ms` field parameter of CreateSession
// and SetFieldParams (and ddgi-server --budget-ms for sessions that set none), taken out of the
// field assignments before the parameter table sees them; the calibration settings and cache
// every session of the server shares; and the choice as FieldParams.budget reports it. The
// choosing itself is tools/field_budget.h. The energy calibration (tools/field_energy.h), which
// shares the calibration machinery and cache, is configured and reported here too.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "tools/field_budget.h"
#include "tools/field_energy.h"

namespace ddgi::service {

inline constexpr const char* kBudgetParam = "budget_ms";
inline constexpr const char* kBudgetParamHelp =
    "GPU milliseconds per frame (field update + frame passes at the server's --budget-frame "
    "size) within which the server picks the field configuration of lowest error it measured "
    "for this scene on this GPU; (0, 1e6], 0 ends the budget. Refused when nothing fits.";

// What every session's budget shares (owned by the Server).
struct BudgetService {
  double default_ms = 0.0;  // sessions that set no budget_ms (--budget-ms); 0: none
  tools::CalibrationOptions calibration;
  // The energy calibration (tools/field_energy.h) of sessions that set none of its parameters,
  // as ServerOptions::energy_calibration and energy_options say. Its calibrations share the
  // cache (keys of their own).
  bool energy = false;
  tools::CalibrationOptions energy_calibration;
  tools::BudgetCache cache;
};

// Takes every "budget_ms=VALUE" out of `assignments` (the last counts): nothing when there is
// none; 0 turns the budget off. A value that is not a number in [0, 1e6] is refused by name.
Result<std::optional<double>> take_budget(std::vector<std::string>& assignments);

void to_proto(const tools::BudgetChoice& choice, v1::FieldBudget* out);
void to_proto(const tools::EnergyChoice& choice, v1::FieldEnergy* out);

}  // namespace ddgi::service
