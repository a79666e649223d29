#include "service/text.h"

#include <cstdio>

namespace ddgi::service {

std::string printable(std::string_view text, size_t max_bytes) {
  std::string out = "'";
  const size_t shown = text.size() > max_bytes ? max_bytes : text.size();
  for (size_t i = 0; i < shown; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f && c != '\\' && c != '\'') {
      out += static_cast<char>(c);
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", c);
      out += escaped;
    }
  }
  if (shown < text.size()) out += "...";
  out += "'";
  return out;
}

}  // namespace ddgi::service
