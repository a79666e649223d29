#include "core/flags.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace ddgi {

Result<double> parse_double(const std::string& text, const std::string& what) {
  double value = 0.0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (text.empty() || ec != std::errc() || ptr != end) {
    return invalid_argument(what + ": '" + text + "' is not a number");
  }
  if (!std::isfinite(value)) return invalid_argument(what + ": '" + text + "' is not finite");
  return value;
}

Result<int64_t> parse_int(const std::string& text, const std::string& what) {
  int64_t value = 0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (text.empty() || ec != std::errc() || ptr != end) {
    return invalid_argument(what + ": '" + text + "' is not an integer");
  }
  return value;
}

Result<Flags> Flags::parse(int argc, char** argv, const std::vector<std::string>& known_flags,
                           const std::vector<std::string>& boolean_flags) {
  Flags flags;
  auto known = [&](const std::string& name) {
    return std::find(known_flags.begin(), known_flags.end(), name) != known_flags.end();
  };
  auto boolean = [&](const std::string& name) {
    return std::find(boolean_flags.begin(), boolean_flags.end(), name) != boolean_flags.end();
  };
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      flags.positional_.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2);
    std::optional<std::string> value;
    if (const size_t eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (boolean(name)) {
      if (value && *value != "true" && *value != "false") {
        return invalid_argument("--" + name + " takes no value (or =true/=false)");
      }
      if (!value || *value == "true") flags.values_[name] = {"true"};
      continue;
    }
    if (!known(name)) return invalid_argument("unknown flag --" + name + " (see --help)");
    if (!value) {
      if (i + 1 >= argc) return invalid_argument("--" + name + " needs a value");
      value = argv[++i];
    }
    flags.values_[name].push_back(*value);
  }
  return flags;
}

Result<std::string> Flags::get_string(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second.back();
}

std::vector<std::string> Flags::get_all(const std::string& name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

Result<double> Flags::get_double(const std::string& name, double fallback, double min,
                                 double max) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  const std::string& text = it->second.back();
  DDGI_ASSIGN_OR_RETURN(const double value, parse_double(text, "--" + name));
  if (value < min || value > max) {
    std::ostringstream out;
    out << "--" << name << " must be in [" << min << ", " << max << "] (got " << text << ")";
    return invalid_argument(out.str());
  }
  return value;
}

Result<int64_t> Flags::get_int(const std::string& name, int64_t fallback, int64_t min,
                               int64_t max) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  const std::string& text = it->second.back();
  DDGI_ASSIGN_OR_RETURN(const int64_t value, parse_int(text, "--" + name));
  if (value < min || value > max) {
    return invalid_argument("--" + name + " must be in [" + std::to_string(min) + ", " +
                            std::to_string(max) + "] (got " + text + ")");
  }
  return value;
}

Result<std::vector<double>> Flags::get_doubles(const std::string& name, size_t min_count,
                                               size_t max_count) const {
  std::vector<double> values;
  const auto it = values_.find(name);
  if (it == values_.end()) return values;
  const std::string& text = it->second.back();
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    DDGI_ASSIGN_OR_RETURN(const double v, parse_double(item, "--" + name));
    values.push_back(v);
  }
  if (values.size() < min_count || values.size() > max_count) {
    return invalid_argument("--" + name + " needs " + std::to_string(min_count) +
                            (min_count == max_count ? "" : " to " + std::to_string(max_count)) +
                            " comma-separated numbers (got '" + text + "')");
  }
  return values;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> pieces(1);
  for (const char c : text) {
    if (c == separator) {
      pieces.emplace_back();
    } else {
      pieces.back() += c;
    }
  }
  return pieces;
}

}  // namespace ddgi
