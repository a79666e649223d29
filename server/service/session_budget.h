// A session's configuration as the service offers it (tools/field_choice.h: the rule): the
// `budget_ms` field parameter of CreateSession and SetFieldParams (ddgi-server --budget-ms for
// sessions that set none), taken out of the field assignments before the parameter table sees
// them; the calibration settings, cache and background calibrator every session of the server
// shares; and what FieldParams.budget and FieldParams.calibration report.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "service/calibrator.h"
#include "tools/field_budget.h"
#include "tools/field_choice.h"

namespace ddgi::service {

inline constexpr const char* kBudgetParam = "budget_ms";
inline constexpr const char* kBudgetParamHelp =
    "GPU milliseconds per frame (every pass: shadow field, field update, frame, at the server's "
    "--budget-frame size) within which the server picks the configuration of lowest error it "
    "measured for this scene on this GPU; (0, 1e6], 0 returns to the server's --budget-ms. Never "
    "refused: where nothing fits, the cheapest configuration streams and FieldParams.budget says "
    "by how much it misses.";

// The share of the GPU's time a background calibration may take: a third, so that streams beside
// it keep two thirds of their frame rate at worst while it runs.
inline constexpr double kDefaultCalibrationShare = 1.0 / 3.0;

// (0, 1]: refused by name otherwise.
Status check_calibration_share(double share);

// What every session's configuration shares (owned by the Server).
struct BudgetService {
  double default_ms = tools::kDefaultBudgetMs;  // sessions that set no budget_ms (--budget-ms)
  tools::CalibrationOptions calibration;
  tools::BudgetCache cache;
  // Scenes are calibrated where there is one (--calibration); else `off_reason` says why not.
  std::unique_ptr<Calibrator> calibrator;
  std::string off_reason;
};

// Takes every "budget_ms=VALUE" out of `assignments` (the last counts): nothing when there is
// none; 0 returns to the server's default. A value that is not a number in [0, 1e6] is refused by
// name.
Result<std::optional<double>> take_budget(std::vector<std::string>& assignments);

void to_proto(const tools::BudgetChoice& choice, const std::string& scene_label,
              v1::FieldBudget* out);

}  // namespace ddgi::service
