// Field parameters by name, as text: the one way the CLI (--field name=value), config files
// and the RPC API read and change IrradianceFieldParams. Setting parses the value; validate()
// checks the ranges of the whole struct afterwards.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"
#include "gi/field_params.h"

namespace ddgi {

struct FieldParamInfo {
  std::string name;
  std::string description;  // the range and the reason, as in field_params.h
};

const std::vector<FieldParamInfo>& field_param_infos();

// Vectors are comma-separated ("0.5,0.5,0.5"). Unknown names and malformed values are errors
// naming the parameter.
Status set_field_param(IrradianceFieldParams& params, const std::string& name,
                       const std::string& value);
Result<std::string> get_field_param(const IrradianceFieldParams& params, const std::string& name);

// Applies "name=value" assignments in order, then validates; `params` is unchanged on error.
Status apply_field_assignments(IrradianceFieldParams& params,
                               const std::vector<std::string>& assignments);

}  // namespace ddgi
