#include "service/auth.h"

#include <fstream>
#include <sstream>

namespace ddgi::service {
namespace {

constexpr std::string_view kPrefix = "Bearer ";

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
  if (value.size() < kPrefix.size() || value.substr(0, kPrefix.size()) != kPrefix ||
      !constant_time_equal(value.substr(kPrefix.size()), token_)) {
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
