// A pre-parse guard: the glTF parser converts `extras` and `extensions` recursively, so a file
// of deeply nested arrays would overflow the stack. Checked on the raw text, allocating nothing.
#pragma once

#include <cstdint>
#include <span>

#include "core/result.h"

namespace ddgi {

// Fails when arrays/objects nest deeper than max_depth. Brackets inside strings are not
// counted; the text need not be valid JSON (the parser reports that).
Status check_json_nesting(std::span<const uint8_t> text, uint32_t max_depth);

}  // namespace ddgi
