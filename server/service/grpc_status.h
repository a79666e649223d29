// The one place where errors-as-values become gRPC statuses (the RPC boundary).
#pragma once

#include <grpcpp/support/status.h>

#include "core/result.h"

namespace ddgi::service {

grpc::StatusCode to_grpc_code(ErrorCode code);
grpc::Status to_grpc(const Error& error);
inline grpc::Status to_grpc(const Status& status) {
  return status.ok() ? grpc::Status::OK : to_grpc(status.error());
}

}  // namespace ddgi::service
