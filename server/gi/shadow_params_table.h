// Shadow-field parameters by name, as text: how the CLI (--shadow-field name=value) reads and
// changes ShadowFieldParams. Setting parses the value; validate() checks the whole struct after.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "gi/shadow_params.h"

namespace ddgi {

struct ShadowParamInfo {
  std::string name;
  std::string description;  // the range and the reason, as in shadow_params.h
};

const std::vector<ShadowParamInfo>& shadow_param_infos();

// Vectors are comma-separated ("0.5,0.5,0.5"); enums by name (weighting=cosine|wrap,
// overflow=shadow-rays|unshadowed); booleans as on/off, true/false or 1/0. Unknown names and
// malformed values are errors naming the parameter.
Status set_shadow_param(ShadowFieldParams& params, const std::string& name,
                        const std::string& value);
Result<std::string> get_shadow_param(const ShadowFieldParams& params, const std::string& name);

// Applies "name=value" assignments in order, then validates; `params` is unchanged on error.
Status apply_shadow_assignments(ShadowFieldParams& params,
                                const std::vector<std::string>& assignments);

}  // namespace ddgi
