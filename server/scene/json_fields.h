// Strict reading of the project's own JSON files (scene sidecars, camera paths): values are
// checked one field at a time, and every error names the key path, what was expected and what
// was there ("lights[2].color: expected an array of 3 numbers, each a finite number >= 0, got
// [1,-1,0]"). Internal to the scene library.
#pragma once

#include <cmath>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/result.h"
#include "scene/finite.h"

namespace ddgi::json_fields {

using json = nlohmann::json;

// "path.key", or "key" at the top level.
std::string join(const std::string& path, const std::string& key);

// The error "PATH: expected WHAT, got VALUE" (long values shortened).
Error expected(const std::string& path, const std::string& what, const json& got);

// A number as short as it reads: 90, 0.5 (no trailing zeros).
std::string number_text(double v);

// The object at `path`, with every key among `allowed`.
Status check_object(const json& value, const std::string& path,
                    std::initializer_list<std::string_view> allowed);

// Parses JSON, refusing repeated keys (nlohmann would keep the last one silently).
Result<json> parse_json_strict(std::span<const uint8_t> text);

// An interval of accepted numbers, each end open or closed; says itself in messages.
struct Range {
  double min = -HUGE_VAL;
  double max = HUGE_VAL;
  bool min_open = false;
  bool max_open = false;

  bool contains(double v) const {
    return (min_open ? v > min : v >= min) && (max_open ? v < max : v <= max);
  }
  std::string text() const;
};

inline constexpr Range kAny{};
inline constexpr Range kNonNegative{0.0};
inline constexpr Range kPositive{0.0, HUGE_VAL, true};
inline constexpr Range kUnit{0.0, 1.0};

// A number in `range` that a float holds.
Result<float> read_number(const json& value, const std::string& path, const Range& range);

// An array of N such numbers.
template <int N>
Result<glm::vec<N, float>> read_vector(const json& value, const std::string& path,
                                       const Range& range) {
  const std::string what = "an array of " + std::to_string(N) + " numbers, each " + range.text();
  if (!value.is_array() || value.size() != N) return expected(path, what, value);
  glm::vec<N, float> result;
  for (int i = 0; i < N; ++i) {
    const json& item = value[static_cast<size_t>(i)];
    if (!item.is_number() || !finite_as_float(item.get<double>()) ||
        !range.contains(item.get<double>())) {
      return expected(path, what, value);
    }
    result[i] = item.get<float>();
  }
  return result;
}

// A non-zero vector of finite length, normalised.
Result<glm::vec3> read_direction(const json& value, const std::string& path);

Result<std::string> read_string(const json& value, const std::string& path);

}  // namespace ddgi::json_fields
