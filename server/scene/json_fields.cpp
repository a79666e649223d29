// Strict reading of the project's own JSON files: see json_fields.h.
#include "scene/json_fields.h"

#include <set>
#include <vector>

namespace ddgi::json_fields {
namespace {

// A short rendering of a bad value for messages.
std::string shown(const json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

}  // namespace

std::string number_text(double v) {
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

Error expected(const std::string& path, const std::string& what, const json& got) {
  return invalid_argument(path + ": expected " + what + ", got " + shown(got));
}

Status check_object(const json& value, const std::string& path,
                    std::initializer_list<std::string_view> allowed) {
  if (!value.is_object()) return expected(path.empty() ? "(top level)" : path, "an object", value);
  for (const auto& [key, unused] : value.items()) {
    bool known = false;
    for (std::string_view name : allowed) known = known || key == name;
    if (!known) {
      std::string names;
      for (std::string_view name : allowed)
        names += (names.empty() ? "" : ", ") + std::string(name);
      return invalid_argument(join(path, key) + ": unknown key (expected one of: " + names + ")");
    }
  }
  return ok_status();
}

Result<json> parse_json_strict(std::span<const uint8_t> text) {
  std::vector<std::set<std::string>> open_objects;
  std::string duplicate;
  auto callback = [&](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) {
      open_objects.emplace_back();
    } else if (event == json::parse_event_t::object_end) {
      if (!open_objects.empty()) open_objects.pop_back();
    } else if (event == json::parse_event_t::key && !open_objects.empty()) {
      const std::string key = parsed.get<std::string>();
      if (!open_objects.back().insert(key).second && duplicate.empty()) duplicate = key;
    }
    return true;
  };
  try {
    json value = json::parse(text.begin(), text.end(), callback);
    if (!duplicate.empty()) return invalid_argument("key '" + duplicate + "' appears twice");
    return value;
  } catch (const json::exception& e) {
    return invalid_argument(std::string("invalid JSON: ") + e.what());
  }
}

std::string Range::text() const {
  if (min == -HUGE_VAL && max == HUGE_VAL) return "a finite number";
  if (max == HUGE_VAL)
    return std::string("a finite number ") + (min_open ? "> " : ">= ") + number_text(min);
  return std::string("a number in ") + (min_open ? "(" : "[") + number_text(min) + ", " +
         number_text(max) + (max_open ? ")" : "]");
}

Result<float> read_number(const json& value, const std::string& path, const Range& range) {
  if (!value.is_number() || !finite_as_float(value.get<double>()) ||
      !range.contains(value.get<double>())) {
    return expected(path, range.text(), value);
  }
  return value.get<float>();
}

Result<glm::vec3> read_direction(const json& value, const std::string& path) {
  DDGI_ASSIGN_OR_RETURN(const glm::vec3 v, read_vector<3>(value, path, kAny));
  const float length = glm::length(v);
  if (!(length > 1e-6f) || !std::isfinite(length)) {
    return expected(path, "a non-zero direction of finite length", value);
  }
  return v / length;
}

Result<std::string> read_string(const json& value, const std::string& path) {
  if (!value.is_string()) return expected(path, "a string", value);
  return value.get<std::string>();
}

}  // namespace ddgi::json_fields
