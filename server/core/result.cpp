#include "core/result.h"

#include "core/enum_names.h"

namespace ddgi {
namespace {

constexpr EnumName<ErrorCode> kErrorCodeNames[] = {
    {ErrorCode::kInvalidArgument, "INVALID_ARGUMENT"},
    {ErrorCode::kNotFound, "NOT_FOUND"},
    {ErrorCode::kResourceExhausted, "RESOURCE_EXHAUSTED"},
    {ErrorCode::kFailedPrecondition, "FAILED_PRECONDITION"},
    {ErrorCode::kUnavailable, "UNAVAILABLE"},
    {ErrorCode::kInternal, "INTERNAL"},
};

}  // namespace

const char* error_code_name(ErrorCode code) {
  return enum_name(kErrorCodeNames, code, "UNKNOWN");
}

}  // namespace ddgi
