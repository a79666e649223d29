// Optional bearer-token auth: every RenderService call must carry the metadata
// "authorization: Bearer <token>" (the scheme in any case, one or more spaces before the token).
// The health service is not ours and stays open, so probes need no secret. Tokens are compared in
// constant time and never logged or echoed.
#pragma once

#include <grpcpp/grpcpp.h>

#include <string>

#include "core/result.h"

namespace ddgi::service {

class BearerAuth {
 public:
  BearerAuth() = default;  // auth off
  explicit BearerAuth(std::string token) : token_(std::move(token)) {}
  bool enabled() const { return !token_.empty(); }
  // OK, or UNAUTHENTICATED saying whether the token was missing or wrong (not what it was).
  grpc::Status check(const grpc::ServerContextBase& context) const;

 private:
  std::string token_;
};

// Reads a token file: surrounding whitespace is trimmed; an empty token, one over 4096 bytes or
// with control characters is INVALID_ARGUMENT (the message never contains the token).
Result<std::string> read_token_file(const std::string& path);

}  // namespace ddgi::service
