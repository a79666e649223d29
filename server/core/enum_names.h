// Names for the values of an enum, kept as one table per enum and looked up both ways, so that
// every enum-to-text mapping (log levels, error codes, RPC status codes) is data rather than
// another switch statement.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace ddgi {

template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name `value` has in `table`; `fallback` when the table does not list it.
template <typename Enum, size_t N>
constexpr const char* enum_name(const EnumName<Enum> (&table)[N], Enum value,
                                const char* fallback) {
  for (const EnumName<Enum>& entry : table) {
    if (entry.value == value) return entry.name;
  }
  return fallback;
}

// The value named `name` in `table`; nullopt when no entry has that name.
template <typename Enum, size_t N>
constexpr std::optional<Enum> enum_value(const EnumName<Enum> (&table)[N], std::string_view name) {
  for (const EnumName<Enum>& entry : table) {
    if (name == entry.name) return entry.value;
  }
  return std::nullopt;
}

}  // namespace ddgi
