// The canonical name of a gRPC status code ("NOT_FOUND"), for messages, logs and metric labels.
// Shared by the server and the clients, which both link the API library beside it.
#pragma once

#include <grpcpp/support/status.h>

namespace ddgi {

// "OK", "CANCELLED", ... "UNAUTHENTICATED"; "UNKNOWN" for a value that is no status code.
const char* status_code_name(grpc::StatusCode code);

}  // namespace ddgi
