// Parameter tables: one declaration per parameter of a parameter struct (its name, its member,
// its range and a short doc), from which everything else about the parameter is derived: the
// range checks validate() starts with, setting and reading it by name as text (ddgi-render
// --field / --shadow-field name=value, config files, the RPC's SetFieldParams / GetFieldParams),
// the help text (--field help, the RPC's parameter list) and the test cases of every range
// (tests/unit/gi/param_table_test.cpp iterates the tables). The default is the struct's member
// initializer, the one place a default lives. The irradiance field and the shadow field declare
// their tables with these builders; a new field type (SH probes, cascades) does the same.
// In gi, not core: the vector kinds are glm's, and every user sits at gi or above.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "core/flags.h"
#include "core/result.h"

namespace ddgi {

// A value a parameter's declared range refuses or accepts, derived from the declaration so that
// no parameter goes without range tests.
template <typename P>
struct ParamExample {
  std::string value;              // as text, for test messages ("1025", "nan,1,1")
  std::function<void(P&)> apply;  // sets the parameter's member to it
  // What the refusal names, e.g. "hysteresis must be in [0, 0.999]"; empty: the range accepts it.
  std::string refusal;
};

template <typename P>
struct ParamSpec {
  std::string name;
  std::string help;  // the short doc and the values allowed, for --field help and the RPC
  // Parses text into the member; errors name the parameter. Ranges are left to `check`, so the
  // order of assignments does not matter.
  std::function<Status(P&, const std::string&)> parse;
  std::function<std::string(const P&)> format;  // text `parse` reads back to the same value
  // The declared range; the message starts with `prefix` ("shadow field ") and names the
  // parameter and its range.
  std::function<Status(const P&, const std::string& prefix)> check;
  std::vector<ParamExample<P>> examples;  // just outside the range (refused) and its bounds
};

template <typename P>
class ParamTable {
 public:
  // `noun` names the parameters in messages ("field parameter"); `prefix` starts every range
  // message ("shadow field ", or nothing). The entries are `specs`, then `more` (a field's
  // table: the grid's entries from probe_grid.h, then its own).
  ParamTable(std::string noun, std::string prefix, std::vector<ParamSpec<P>> specs,
             std::vector<ParamSpec<P>> more = {})
      : noun_(std::move(noun)), prefix_(std::move(prefix)), specs_(std::move(specs)) {
    for (ParamSpec<P>& spec : more) specs_.push_back(std::move(spec));
  }

  const std::vector<ParamSpec<P>>& specs() const { return specs_; }
  const std::string& prefix() const { return prefix_; }
  const ParamSpec<P>* find(const std::string& name) const {
    for (const ParamSpec<P>& spec : specs_) {
      if (spec.name == name) return &spec;
    }
    return nullptr;
  }

  // Unknown names and malformed values are errors naming the parameter.
  Status set(P& params, const std::string& name, const std::string& value) const {
    const ParamSpec<P>* spec = find(name);
    if (!spec) return unknown(name);
    return spec->parse(params, value);
  }
  Result<std::string> get(const P& params, const std::string& name) const {
    const ParamSpec<P>* spec = find(name);
    if (!spec) return unknown(name);
    return spec->format(params);
  }

  // Every parameter's declared range, in table order: the start of validate().
  Status check(const P& params) const {
    for (const ParamSpec<P>& spec : specs_) DDGI_TRY(spec.check(params, prefix_));
    return ok_status();
  }

  // Applies "name=value" assignments in order, then validate(P) (found by argument-dependent
  // lookup: the struct's own, with its rules across parameters); `params` is unchanged on error.
  Status apply(P& params, const std::vector<std::string>& assignments) const {
    P updated = params;
    for (const std::string& a : assignments) {
      const size_t eq = a.find('=');
      if (eq == std::string::npos) {
        return invalid_argument(noun_ + " assignment '" + a + "' is not name=value");
      }
      DDGI_TRY(set(updated, a.substr(0, eq), a.substr(eq + 1)));
    }
    DDGI_TRY(validate(updated));
    params = updated;
    return ok_status();
  }

  // One line per parameter: its name, then its help.
  std::string help() const {
    std::string text;
    for (const ParamSpec<P>& spec : specs_) {
      text += "  " + spec.name +
              std::string(spec.name.size() < 28 ? 28 - spec.name.size() : 0, ' ') + " " +
              spec.help + "\n";
    }
    return text;
  }

 private:
  Error unknown(const std::string& name) const {
    std::string names;
    for (const ParamSpec<P>& spec : specs_) names += (names.empty() ? "" : ", ") + spec.name;
    return invalid_argument("unknown " + noun_ + " '" + name + "' (known: " + names + ")");
  }

  std::string noun_;
  std::string prefix_;
  std::vector<ParamSpec<P>> specs_;
};

namespace param_detail {

// Numbers as messages print them (the stream's default precision: "0.999", "1e-30").
template <typename T>
std::string text(T value) {
  std::ostringstream out;
  out << value;
  return out.str();
}
// Numbers as `format` writes them: floats with 9 significant digits, which read back exactly.
std::string exact(double value);
template <typename T>
std::string range_message(const std::string& name, T min, T max) {
  return name + " must be in [" + text(min) + ", " + text(max) + "]";
}
// "a or b", "a, b or c".
std::string join_or(const std::vector<std::string>& words);
// A non-negative integer up to `max` (errors name `name`).
Result<uint64_t> parse_unsigned(const std::string& name, const std::string& text, uint64_t max);
// Three comma-separated finite numbers; errors name `name`.
Result<glm::dvec3> parse_vec3(const std::string& name, const std::string& text);

}  // namespace param_detail

// The builders of table entries.
namespace param {

// A number in [min, max], both included (NaN is refused). Floats are read as finite decimals,
// unsigned integers as non-negative integers of their type.
template <typename P, typename T>
ParamSpec<P> number(std::string name, T P::*member, std::type_identity_t<T> min,
                    std::type_identity_t<T> max, std::string doc) {
  static_assert(std::is_floating_point_v<T> || std::is_unsigned_v<T>);
  using Limits = std::numeric_limits<T>;
  ParamSpec<P> spec;
  spec.name = name;
  const bool bounded = min != Limits::lowest() || max != Limits::max();
  spec.help =
      bounded ? doc + ", [" + param_detail::text(min) + ", " + param_detail::text(max) + "]" : doc;
  spec.parse = [name, member](P& p, const std::string& text) -> Status {
    if constexpr (std::is_floating_point_v<T>) {
      DDGI_ASSIGN_OR_RETURN(const double v, parse_double(text, name));
      p.*member = static_cast<T>(v);
    } else {
      DDGI_ASSIGN_OR_RETURN(const uint64_t v,
                            param_detail::parse_unsigned(name, text, Limits::max()));
      p.*member = static_cast<T>(v);
    }
    return ok_status();
  };
  spec.format = [member](const P& p) {
    if constexpr (std::is_floating_point_v<T>) {
      return param_detail::exact(p.*member);
    } else {
      return std::to_string(p.*member);
    }
  };
  const std::string refusal = param_detail::range_message(name, min, max);
  spec.check = [member, min, max, refusal](const P& p, const std::string& prefix) -> Status {
    const T v = p.*member;
    if (v >= min && v <= max) return ok_status();
    return invalid_argument(prefix + refusal + " (got " + param_detail::text(v) + ")");
  };
  auto example = [&](T value, std::string why) {
    spec.examples.push_back(
        {param_detail::text(value), [member, value](P& p) { p.*member = value; }, std::move(why)});
  };
  if constexpr (std::is_floating_point_v<T>) {
    example(Limits::quiet_NaN(), refusal);
    if (min > -Limits::infinity()) example(std::nextafter(min, -Limits::infinity()), refusal);
    if (max < Limits::infinity()) example(std::nextafter(max, Limits::infinity()), refusal);
  } else {
    if (min > Limits::lowest()) example(T(min - 1), refusal);
    if (max < Limits::max()) example(T(max + 1), refusal);
  }
  example(min, "");
  example(max, "");
  return spec;
}

// A number any value of whose type is valid (a seed), or whose limits are rules across
// parameters that validate() states.
template <typename P, typename T>
ParamSpec<P> number(std::string name, T P::*member, std::string doc) {
  using Limits = std::numeric_limits<T>;
  return number(std::move(name), member, Limits::lowest(), Limits::max(), std::move(doc));
}

// How a boolean is written back; either spelling (and on/off, true/false, 1/0) is read.
enum class BoolWords { kTrueFalse, kOnOff };

template <typename P>
ParamSpec<P> flag(std::string name, bool P::*member, BoolWords words, std::string doc) {
  const std::string yes = words == BoolWords::kOnOff ? "on" : "true";
  const std::string no = words == BoolWords::kOnOff ? "off" : "false";
  ParamSpec<P> spec;
  spec.name = name;
  spec.help = doc + ", " + yes + " | " + no;
  spec.parse = [name, member, yes, no](P& p, const std::string& text) -> Status {
    if (text == "on" || text == "true" || text == "1") {
      p.*member = true;
    } else if (text == "off" || text == "false" || text == "0") {
      p.*member = false;
    } else {
      return invalid_argument(name + " must be " + yes + " or " + no + " (got '" + text + "')");
    }
    return ok_status();
  };
  spec.format = [member, yes, no](const P& p) { return p.*member ? yes : no; };
  spec.check = [](const P&, const std::string&) { return ok_status(); };
  for (const bool value : {false, true}) {
    spec.examples.push_back({value ? yes : no, [member, value](P& p) { p.*member = value; }, ""});
  }
  return spec;
}

// An enum by name: each value the parameter may take, with its name.
template <typename E>
using ParamNames = std::vector<std::pair<std::string, E>>;

namespace detail {

// Enums, optional or not, through std::optional<E> (nullopt only when `none` names it).
template <typename P, typename E>
ParamSpec<P> choice(std::string name, std::string doc, std::optional<std::string> none,
                    ParamNames<E> names, std::function<std::optional<E>(const P&)> get,
                    std::function<void(P&, std::optional<E>)> put) {
  std::vector<std::string> words;
  if (none) words.push_back(*none);
  for (const auto& [word, value] : names) words.push_back(word);
  std::string alternatives;
  for (const std::string& word : words) alternatives += (alternatives.empty() ? "" : " | ") + word;
  const std::string must = name + " must be " + param_detail::join_or(words);
  auto name_of = [none, names](std::optional<E> value) -> std::optional<std::string> {
    if (!value) return none;
    for (const auto& [word, v] : names) {
      if (v == *value) return word;
    }
    return std::nullopt;
  };
  ParamSpec<P> spec;
  spec.name = name;
  spec.help = doc + ", " + alternatives;
  spec.parse = [none, names, put, must](P& p, const std::string& text) -> Status {
    if (none && text == *none) {
      put(p, std::nullopt);
      return ok_status();
    }
    for (const auto& [word, value] : names) {
      if (text == word) {
        put(p, value);
        return ok_status();
      }
    }
    return invalid_argument(must + " (got '" + text + "')");
  };
  auto number_of = [](E value) { return std::to_string(std::underlying_type_t<E>(value)); };
  // An unnamed value (only ever set in code, and refused by check) is written as its number.
  spec.format = [get, name_of, number_of](const P& p) {
    const std::optional<E> value = get(p);
    if (const std::optional<std::string> word = name_of(value)) return *word;
    return number_of(*value);
  };
  spec.check = [get, name_of, number_of, must](const P& p, const std::string& prefix) -> Status {
    const std::optional<E> value = get(p);
    if (name_of(value)) return ok_status();
    return invalid_argument(prefix + must + " (got " + number_of(*value) + ")");
  };
  std::underlying_type_t<E> unnamed = 0;
  for (const auto& [word, value] : names) {
    unnamed = std::max(unnamed, std::underlying_type_t<E>(std::underlying_type_t<E>(value) + 1));
    spec.examples.push_back({word, [put, v = value](P& p) { put(p, v); }, ""});
  }
  if (none) spec.examples.push_back({*none, [put](P& p) { put(p, std::nullopt); }, ""});
  spec.examples.push_back(
      {number_of(E(unnamed)), [put, unnamed](P& p) { put(p, E(unnamed)); }, must});
  return spec;
}

}  // namespace detail

template <typename P, typename E>
ParamSpec<P> choice(std::string name, E P::*member, ParamNames<E> names, std::string doc) {
  return detail::choice<P, E>(
      std::move(name), std::move(doc), std::nullopt, std::move(names),
      [member](const P& p) { return std::optional<E>(p.*member); },
      [member](P& p, std::optional<E> value) { p.*member = *value; });
}

// An optional enum: `none` names the empty value.
template <typename P, typename E>
ParamSpec<P> choice(std::string name, std::optional<E> P::*member, std::string none,
                    ParamNames<E> names, std::string doc) {
  return detail::choice<P, E>(
      std::move(name), std::move(doc), std::move(none), std::move(names),
      [member](const P& p) { return p.*member; },
      [member](P& p, std::optional<E> value) { p.*member = value; });
}

// A 3-vector, written "x,y,z".
enum class VectorRange {
  kFinite,    // a position
  kPositive,  // finite and > 0 on every axis: a size
};

template <typename P>
ParamSpec<P> vec3(std::string name, glm::vec3 P::*member, VectorRange range, std::string doc) {
  using Limits = std::numeric_limits<float>;
  const bool positive = range == VectorRange::kPositive;
  const std::string refusal =
      name + (positive ? " must be finite and > 0 on every axis" : " must be finite");
  ParamSpec<P> spec;
  spec.name = name;
  spec.help = doc + (positive ? ", x,y,z each finite and > 0" : ", x,y,z finite");
  spec.parse = [name, member](P& p, const std::string& text) -> Status {
    DDGI_ASSIGN_OR_RETURN(const glm::dvec3 v, param_detail::parse_vec3(name, text));
    p.*member = glm::vec3(v);
    return ok_status();
  };
  spec.format = [member](const P& p) {
    const glm::vec3 v = p.*member;
    return param_detail::exact(v.x) + "," + param_detail::exact(v.y) + "," +
           param_detail::exact(v.z);
  };
  spec.check = [member, positive, refusal](const P& p, const std::string& prefix) -> Status {
    const glm::vec3 v = p.*member;
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(v[axis]) || (positive && !(v[axis] > 0.0f))) {
        return invalid_argument(prefix + refusal);
      }
    }
    return ok_status();
  };
  auto example = [&](glm::vec3 value, const std::string& why) {
    spec.examples.push_back({param_detail::text(value.x) + "," + param_detail::text(value.y) + "," +
                                 param_detail::text(value.z),
                             [member, value](P& p) { p.*member = value; }, why});
  };
  const float nan = Limits::quiet_NaN();
  const float inf = Limits::infinity();
  example({nan, 1, 1}, refusal);
  example({1, inf, 1}, refusal);
  example({1, 1, -inf}, refusal);
  if (positive) {
    example({1, 1, 0}, refusal);
    example({-1, 1, 1}, refusal);
    example({Limits::denorm_min(), 1, Limits::max()}, "");
  } else {
    example({Limits::lowest(), 0, Limits::max()}, "");
  }
  return spec;
}

// Probes per axis of a grid, each in [min, max], at most `max_total` probes in all; written
// "x,y,z".
template <typename P>
ParamSpec<P> probe_counts(std::string name, glm::ivec3 P::*member, int min, int max,
                          uint64_t max_total, std::string doc) {
  ParamSpec<P> spec;
  spec.name = name;
  spec.help = doc + ", each in [" + std::to_string(min) + ", " + std::to_string(max) +
              "], total <= " + std::to_string(max_total);
  spec.parse = [name, member](P& p, const std::string& text) -> Status {
    DDGI_ASSIGN_OR_RETURN(const glm::dvec3 v, param_detail::parse_vec3(name, text));
    for (int axis = 0; axis < 3; ++axis) {
      if (v[axis] != double(int64_t(v[axis])) || v[axis] < 0 || v[axis] > 1e6) {
        return invalid_argument(name + " must be three integers (got '" + text + "')");
      }
    }
    p.*member = glm::ivec3(v);
    return ok_status();
  };
  spec.format = [member](const P& p) {
    const glm::ivec3 c = p.*member;
    return std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z);
  };
  const char* axes[] = {".x", ".y", ".z"};
  std::vector<std::string> refusals;
  for (const char* axis : axes) {
    refusals.push_back(param_detail::range_message(name + axis, min, max));
  }
  const std::string too_many = " probes; at most " + std::to_string(max_total) + " are allowed";
  spec.check = [name, member, min, max, max_total, refusals, too_many](
                   const P& p, const std::string& prefix) -> Status {
    const glm::ivec3 c = p.*member;
    uint64_t total = 1;
    for (int axis = 0; axis < 3; ++axis) {
      if (c[axis] < min || c[axis] > max) {
        return invalid_argument(prefix + refusals[axis] + " (got " + std::to_string(c[axis]) + ")");
      }
      total *= uint64_t(c[axis]);
    }
    if (total > max_total) {
      return invalid_argument(prefix + name + " give " + std::to_string(total) + too_many);
    }
    return ok_status();
  };
  auto example = [&](glm::ivec3 value, const std::string& why) {
    spec.examples.push_back(
        {std::to_string(value.x) + "," + std::to_string(value.y) + "," + std::to_string(value.z),
         [member, value](P& p) { p.*member = value; }, why});
  };
  example({min - 1, min, min}, refusals[0]);
  example({min, min - 1, min}, refusals[1]);
  example({min, min, max + 1}, refusals[2]);
  const uint64_t largest = uint64_t(max) * uint64_t(max) * uint64_t(max);
  if (largest > max_total) {
    example({max, max, max}, name + " give " + std::to_string(largest) + too_many);
  }
  example({min, min, min}, "");
  example({max, min, min}, "");
  return spec;
}

}  // namespace param
}  // namespace ddgi
