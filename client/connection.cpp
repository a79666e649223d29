#include "connection.h"

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ddgi::client {

Result<std::string> read_text(const std::string& path, const char* what) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return not_found(std::string("cannot read the ") + what + " " + path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

namespace {

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  const auto last = text.find_last_not_of(" \t\r\n");
  return first == std::string::npos ? "" : text.substr(first, last - first + 1);
}

}  // namespace

const std::vector<std::string>& connection_flags() {
  static const std::vector<std::string> flags = {"server", "tls-ca", "tls-server-name",
                                                 "token-file", "deadline"};
  return flags;
}

const char* connection_usage() {
  return R"(connection:
  --server HOST:PORT      the ddgi-server      [$DDGI_SERVER, else localhost:50051]
  --tls                   connect with TLS (system roots unless --tls-ca)
  --tls-ca FILE           PEM roots to trust (implies --tls)
  --tls-server-name NAME  the name the server certificate must carry
  --token-file FILE       send "authorization: Bearer <token>"   [$DDGI_TOKEN]
  --deadline S            seconds each unary call may take         [60]
)";
}

Result<ConnectionOptions> connection_options(const Flags& flags) {
  ConnectionOptions options;
  if (const char* env = std::getenv("DDGI_SERVER"); env && *env) options.server = env;
  DDGI_ASSIGN_OR_RETURN(options.server, flags.get_string("server", options.server));
  DDGI_ASSIGN_OR_RETURN(const std::string ca_file, flags.get_string("tls-ca", ""));
  options.tls = flags.has("tls") || !ca_file.empty();
  if (!ca_file.empty()) {
    DDGI_ASSIGN_OR_RETURN(options.tls_ca_pem, read_text(ca_file, "TLS CA file"));
  }
  DDGI_ASSIGN_OR_RETURN(options.tls_server_name, flags.get_string("tls-server-name", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string token_file, flags.get_string("token-file", ""));
  if (!token_file.empty()) {
    DDGI_ASSIGN_OR_RETURN(const std::string token, read_text(token_file, "token file"));
    options.token = trim(token);
    if (options.token.empty())
      return invalid_argument("the token file " + token_file + " is empty");
  } else if (const char* env = std::getenv("DDGI_TOKEN"); env && *env) {
    options.token = trim(env);
  }
  DDGI_ASSIGN_OR_RETURN(options.deadline_seconds, flags.get_double("deadline", 60.0, 0.001, 1e6));
  return options;
}

std::shared_ptr<grpc::Channel> make_channel(const ConnectionOptions& options) {
  grpc::ChannelArguments args;
  // Frames and atlas chunks can be large; the server enforces its own limits.
  args.SetMaxReceiveMessageSize(256 << 20);
  args.SetMaxSendMessageSize(1 << 30);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, 30000);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 10000);
  if (!options.tls_server_name.empty()) {
    args.SetSslTargetNameOverride(options.tls_server_name);
  }
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  if (options.tls) {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = options.tls_ca_pem;
    credentials = grpc::SslCredentials(ssl);
  }
  return grpc::CreateCustomChannel(options.server, credentials, args);
}

void prepare(grpc::ClientContext& context, const ConnectionOptions& options, bool deadline) {
  if (!options.token.empty()) context.AddMetadata("authorization", "Bearer " + options.token);
  if (deadline) {
    context.set_deadline(std::chrono::system_clock::now() +
                         std::chrono::microseconds(int64_t(options.deadline_seconds * 1e6)));
  }
}

}  // namespace ddgi::client
