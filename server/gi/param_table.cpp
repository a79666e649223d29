// The parts of the parameter tables (param_table.h) that do not depend on the struct.
#include "gi/param_table.h"

#include <charconv>
#include <sstream>

namespace ddgi::param_detail {

std::string exact(double value) {
  std::ostringstream out;
  out.precision(9);
  out << value;
  return out.str();
}

std::string join_or(const std::vector<std::string>& words) {
  std::string text;
  for (size_t i = 0; i < words.size(); ++i) {
    if (i > 0) text += i + 1 == words.size() ? " or " : ", ";
    text += words[i];
  }
  return text;
}

Result<uint64_t> parse_unsigned(const std::string& name, const std::string& text, uint64_t max) {
  uint64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (!text.empty() && ec == std::errc() && ptr == end && value <= max) return value;
  // Not one: say whether it is an integer at all ("-1", "1x").
  DDGI_TRY(parse_int(text, name));
  return invalid_argument(name + " must be a non-negative integer");
}

Result<glm::dvec3> parse_vec3(const std::string& name, const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    DDGI_ASSIGN_OR_RETURN(const double v, parse_double(item, name));
    values.push_back(v);
  }
  if (values.size() != 3) {
    return invalid_argument(name + " needs 3 comma-separated values (got '" + text + "')");
  }
  return glm::dvec3(values[0], values[1], values[2]);
}

}  // namespace ddgi::param_detail
