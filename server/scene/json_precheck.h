// Checks on glTF or sidecar JSON text before the real parse. The glTF parser converts
// `extras` and `extensions` recursively (deep nesting would overflow its stack) and narrows
// every integer index to int (4294967296 would silently become index 0), so both are bounded
// here first, with a streaming parse that builds nothing.
#pragma once

#include <cstdint>
#include <span>

#include "core/result.h"

namespace ddgi {

// Fails on invalid JSON, on arrays/objects nested deeper than max_depth, and on integers
// outside [-2^31, 2^32 - 1] anywhere but inside `extras` (no glTF quantity this loader
// accepts is larger: files are under 4 GiB).
Status precheck_json(std::span<const uint8_t> text, uint32_t max_depth);

}  // namespace ddgi
