#include "scene/json_nesting.h"

#include <string>

namespace ddgi {

Status check_json_nesting(std::span<const uint8_t> text, uint32_t max_depth) {
  uint32_t depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const uint8_t c = text[i];
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        return invalid_argument("JSON nests arrays/objects deeper than " +
                                std::to_string(max_depth) + " levels (at byte " +
                                std::to_string(i) + ")");
      }
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return ok_status();
}

}  // namespace ddgi
