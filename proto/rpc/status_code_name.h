// The canonical name of a gRPC status code ("NOT_FOUND"), for messages, logs and metric labels.
// Shared by the server and the clients, which both link the API library beside it.
#pragma once

#include <grpcpp/support/status.h>

#include <string_view>

namespace ddgi {

// "OK", "CANCELLED", ... "UNAUTHENTICATED"; "UNKNOWN" for a value that is no status code.
const char* status_code_name(grpc::StatusCode code);
// The code of a name status_code_name gives (as the web front's replies carry them); UNKNOWN
// for any other text.
grpc::StatusCode status_code_from_name(std::string_view name);

}  // namespace ddgi
