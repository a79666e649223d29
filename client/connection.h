// How the thin clients reach a ddgi-server: address, optional TLS, optional bearer token,
// deadlines. Shared by ddgi-client and ddgi-viewer.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "core/flags.h"
#include "core/result.h"
#include "rpc/status_code_name.h"  // status_code_name(), for every client

namespace ddgi::client {

struct ConnectionOptions {
  std::string server = "localhost:50051";
  bool tls = false;
  std::string tls_ca_pem;       // empty with tls: the system's roots
  std::string tls_server_name;  // overrides the name checked against the certificate
  std::string token;            // bearer token; never printed
  double deadline_seconds = 60.0;
};

// The connection flags every client takes (connection_usage() lists them).
const std::vector<std::string>& connection_flags();
const char* connection_usage();
// From --server, --tls, --tls-ca, --tls-server-name, --token-file, --deadline, and the
// environment (DDGI_SERVER, DDGI_TOKEN).
Result<ConnectionOptions> connection_options(const Flags& flags);
// A whole file's bytes; NOT_FOUND naming `what` and the path when it cannot be read.
Result<std::string> read_text(const std::string& path, const char* what);

std::shared_ptr<grpc::Channel> make_channel(const ConnectionOptions& options);
// Adds the token and, when `deadline` is set, the deadline.
void prepare(grpc::ClientContext& context, const ConnectionOptions& options, bool deadline = true);

}  // namespace ddgi::client
