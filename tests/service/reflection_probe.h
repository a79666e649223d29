// Asks a server's reflection service to list its services, built by hand (the reflection client
// library is not packaged): one ServerReflectionInfo call with `list_services`.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

namespace ddgi::test {

struct ReflectionAnswer {
  grpc::Status status;  // OK when an answer came; else how the call ended
  std::string text;     // the answer's bytes (service names appear verbatim)
};

ReflectionAnswer list_services(const std::shared_ptr<grpc::Channel>& channel);

}  // namespace ddgi::test
