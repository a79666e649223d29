// Errors are values until the RPC boundary: every fallible run-time operation returns
// Result<T>, and only the service layer turns an Error into a grpc::Status.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace ddgi {

// Mirrors the gRPC status codes we use, so the service maps them one to one.
enum class ErrorCode {
  kInvalidArgument,
  kNotFound,
  kResourceExhausted,
  kFailedPrecondition,
  kUnavailable,
  kInternal,
};

const char* error_code_name(ErrorCode code);

struct Error {
  ErrorCode code = ErrorCode::kInternal;
  std::string message;

  // Prefixes the message with where the error happened ("scene.gltf: ...").
  Error with_context(const std::string& context) const {
    return Error{code, context + ": " + message};
  }
};

inline Error invalid_argument(std::string message) {
  return Error{ErrorCode::kInvalidArgument, std::move(message)};
}
inline Error not_found(std::string message) {
  return Error{ErrorCode::kNotFound, std::move(message)};
}
inline Error resource_exhausted(std::string message) {
  return Error{ErrorCode::kResourceExhausted, std::move(message)};
}
inline Error failed_precondition(std::string message) {
  return Error{ErrorCode::kFailedPrecondition, std::move(message)};
}
inline Error unavailable(std::string message) {
  return Error{ErrorCode::kUnavailable, std::move(message)};
}
inline Error internal_error(std::string message) {
  return Error{ErrorCode::kInternal, std::move(message)};
}

template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : state_(std::move(error)) {}  // NOLINT: implicit by design

  bool ok() const { return state_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & {
    assert(ok());
    return std::get<0>(state_);
  }
  const T& value() const& {
    assert(ok());
    return std::get<0>(state_);
  }
  T&& value() && {
    assert(ok());
    return std::get<0>(std::move(state_));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const Error& error() const {
    assert(!ok());
    return std::get<1>(state_);
  }

 private:
  std::variant<T, Error> state_;
};

// Result<void>: success carries nothing.
struct Ok {};
using Status = Result<Ok>;
inline Status ok_status() {
  return Ok{};
}

}  // namespace ddgi

// Propagates an error from an expression returning Result<T>/Status.
#define DDGI_CONCAT_INNER(a, b) a##b
#define DDGI_CONCAT(a, b) DDGI_CONCAT_INNER(a, b)
#define DDGI_TRY(expr)                                           \
  do {                                                           \
    auto ddgi_try_status_ = (expr);                              \
    if (!ddgi_try_status_.ok()) return ddgi_try_status_.error(); \
  } while (0)
// DDGI_ASSIGN_OR_RETURN(auto x, make_x());
#define DDGI_ASSIGN_OR_RETURN(lhs, expr) \
  DDGI_ASSIGN_OR_RETURN_IMPL(DDGI_CONCAT(ddgi_result_, __LINE__), lhs, expr)
#define DDGI_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                               \
  if (!tmp.ok()) return tmp.error();               \
  lhs = std::move(tmp).value()
