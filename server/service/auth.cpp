#include "service/auth.h"

#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

namespace ddgi::service {
namespace {

constexpr std::string_view kScheme = "bearer";

bool equals_ignoring_case(std::string_view a, std::string_view lower) {
  if (a.size() != lower.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const char c = a[i] >= 'A' && a[i] <= 'Z' ? static_cast<char>(a[i] - 'A' + 'a') : a[i];
    if (c != lower[i]) return false;
  }
  return true;
}

// The credentials of "authorization: <scheme> 1*SP <token>" when the scheme is Bearer in any
// case (RFC 9110 section 11.1: schemes are case-insensitive); nullopt otherwise.
std::optional<std::string_view> bearer_credentials(std::string_view value) {
  const size_t space = value.find(' ');
  if (space == std::string_view::npos || !equals_ignoring_case(value.substr(0, space), kScheme)) {
    return std::nullopt;
  }
  const size_t token = value.find_first_not_of(' ', space);
  if (token == std::string_view::npos) return std::nullopt;
  return value.substr(token);
}

bool constant_time_equal(std::string_view a, std::string_view b) {
  // Length is not secret enough to hide; the bytes are.
  if (a.size() != b.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  }
  return difference == 0;
}

}  // namespace

grpc::Status BearerAuth::check(const grpc::ServerContextBase& context) const {
  if (!enabled()) return grpc::Status::OK;
  const auto& metadata = context.client_metadata();
  auto it = metadata.find("authorization");
  if (it == metadata.end()) {
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                        "missing 'authorization: Bearer <token>' metadata; this server "
                        "requires a bearer token");
  }
  const std::string_view value(it->second.data(), it->second.size());
  const std::optional<std::string_view> presented = bearer_credentials(value);
  if (!presented || !constant_time_equal(*presented, token_)) {
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, "invalid bearer token");
  }
  return grpc::Status::OK;
}

Result<std::string> read_token_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return not_found("cannot read the token file " + path);
  std::ostringstream text;
  text << file.rdbuf();
  std::string token = text.str();
  const auto first = token.find_first_not_of(" \t\r\n");
  const auto last = token.find_last_not_of(" \t\r\n");
  token = first == std::string::npos ? "" : token.substr(first, last - first + 1);
  if (token.empty()) return invalid_argument("the token file " + path + " is empty");
  if (token.size() > 4096) {
    return invalid_argument("the token in " + path + " is longer than 4096 bytes");
  }
  for (char c : token) {
    if (static_cast<unsigned char>(c) < 0x21 || static_cast<unsigned char>(c) > 0x7e) {
      return invalid_argument("the token in " + path +
                              " has a character that is not printable ASCII");
    }
  }
  return token;
}

}  // namespace ddgi::service
