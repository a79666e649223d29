#include "scene/json_precheck.h"

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ddgi {
namespace {

using json = nlohmann::json;

constexpr int64_t kMinInteger = -(int64_t{1} << 31);
constexpr uint64_t kMaxInteger = (uint64_t{1} << 32) - 1;

class PrecheckHandler : public nlohmann::json_sax<json> {
 public:
  explicit PrecheckHandler(uint32_t max_depth) : max_depth_(max_depth) {}

  const std::string& error() const { return error_; }

  bool null() override { return value_done(); }
  bool boolean(bool) override { return value_done(); }
  bool number_integer(number_integer_t value) override {
    if (!next_in_extras_ && value < kMinInteger) return out_of_range(std::to_string(value));
    return value_done();
  }
  bool number_unsigned(number_unsigned_t value) override {
    if (!next_in_extras_ && value > kMaxInteger) return out_of_range(std::to_string(value));
    return value_done();
  }
  bool number_float(number_float_t, const string_t&) override { return value_done(); }
  bool string(string_t&) override { return value_done(); }
  bool binary(binary_t&) override { return value_done(); }
  bool start_object(std::size_t) override { return open(); }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(); }
  bool end_array() override { return close(); }
  bool key(string_t& name) override {
    key_ = name;
    next_in_extras_ = in_extras() || name == "extras";
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    error_ = std::string("invalid JSON: ") + e.what();
    return false;
  }

 private:
  // Whether the innermost open container lies inside an `extras` value.
  bool in_extras() const { return !extras_.empty() && extras_.back(); }
  // After a value, the next one (an array element or a key's value) is inside `extras` only
  // if its container is.
  bool value_done() {
    next_in_extras_ = in_extras();
    return true;
  }
  bool open() {
    if (extras_.size() >= max_depth_) {
      error_ = "JSON nests arrays/objects deeper than " + std::to_string(max_depth_) + " levels";
      return false;
    }
    extras_.push_back(next_in_extras_);
    return value_done();
  }
  bool close() {
    extras_.pop_back();
    return value_done();
  }
  bool out_of_range(const std::string& value) {
    error_ = "integer " + value + (key_.empty() ? "" : " (under key '" + key_ + "')") +
             " is outside [-2147483648, 4294967295]; no glTF quantity is that large";
    return false;
  }

  uint32_t max_depth_;
  std::vector<bool> extras_;     // per open container: inside an `extras` value
  bool next_in_extras_ = false;  // for the value about to be read
  std::string key_;
  std::string error_;
};

}  // namespace

Status precheck_json(std::span<const uint8_t> text, uint32_t max_depth) {
  PrecheckHandler handler(max_depth);
  try {
    if (!json::sax_parse(text.begin(), text.end(), &handler)) {
      return invalid_argument(handler.error().empty() ? "invalid JSON" : handler.error());
    }
  } catch (const std::exception& e) {
    return invalid_argument(std::string("invalid JSON: ") + e.what());
  }
  return ok_status();
}

}  // namespace ddgi
