// Client-sent text shown in messages and logs: escaped and shortened, so a hostile name can
// neither forge log lines nor flood them.
#pragma once

#include <string>
#include <string_view>

namespace ddgi::service {

// 'text' in single quotes; bytes outside printable ASCII become \xNN; longer than `max_bytes`
// is cut and marked with "...".
std::string printable(std::string_view text, size_t max_bytes = 64);

}  // namespace ddgi::service
