// A small strict command-line parser shared by every executable: `--name value` and
// `--name=value`, typed accessors that reject trailing garbage, NaN/Inf and out-of-range
// numbers with a message naming the flag.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi {

class Flags {
 public:
  // `boolean_flags`: flags that take no value (e.g. "validation", "help").
  static Result<Flags> parse(int argc, char** argv, const std::vector<std::string>& known_flags,
                             const std::vector<std::string>& boolean_flags);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }

  Result<std::string> get_string(const std::string& name, const std::string& fallback) const;
  Result<double> get_double(const std::string& name, double fallback, double min, double max) const;
  Result<int64_t> get_int(const std::string& name, int64_t fallback, int64_t min,
                          int64_t max) const;
  // Every value of a flag given several times, in order.
  std::vector<std::string> get_all(const std::string& name) const;
  // A comma-separated list of exactly `count` finite numbers ("1,2,3").
  Result<std::vector<double>> get_doubles(const std::string& name, size_t min_count,
                                          size_t max_count) const;

 private:
  std::map<std::string, std::vector<std::string>> values_;  // a flag may repeat
  std::vector<std::string> positional_;
};

// The pieces of `text` between `separator`s, empty ones included ("" is one empty piece), so
// that a caller can refuse "1,,2" by name.
std::vector<std::string> split(const std::string& text, char separator);

// Strict parsing of a whole string; errors name `what`.
Result<double> parse_double(const std::string& text, const std::string& what);
Result<int64_t> parse_int(const std::string& text, const std::string& what);

}  // namespace ddgi
