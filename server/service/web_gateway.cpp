#include "service/web_gateway.h"

#include <civetweb.h>

#include <filesystem>

#include "core/log.h"
#include "service/web_connection.h"
#include "service/web_scene_download.h"

namespace ddgi::service {
namespace {

// A pattern no file name matches: civetweb runs no CGI and no server-side includes here.
constexpr const char* kNothing = "**.never-served-as-a-script$";

Status validate(const WebOptions& options) {
  if (options.port < 0 || options.port > 65535) {
    return invalid_argument("--web-port " + std::to_string(options.port) +
                            " is out of range [0, 65535] (-1: off)");
  }
  if (options.max_connections < 1 || options.max_connections > 1024) {
    return invalid_argument("--web-max-connections " + std::to_string(options.max_connections) +
                            " is out of range [1, 1024]");
  }
  std::error_code error;
  if (!std::filesystem::is_regular_file(std::filesystem::path(options.root) / "index.html",
                                        error)) {
    return invalid_argument("--web-root '" + options.root +
                            "' holds no index.html (the repo's web/ folder is the web client)");
  }
  return ok_status();
}

}  // namespace

WebGateway::WebGateway(std::shared_ptr<grpc::Channel> channel, Metrics& metrics,
                       int max_connections)
    : stub_(v1::RenderService::NewStub(channel)),
      metrics_(metrics),
      max_connections_(max_connections) {}

Result<std::unique_ptr<WebGateway>> WebGateway::start(const WebOptions& options,
                                                      std::shared_ptr<grpc::Channel> channel,
                                                      Metrics& metrics) {
  DDGI_TRY(validate(options));
  std::unique_ptr<WebGateway> gateway(
      new WebGateway(std::move(channel), metrics, options.max_connections));
  // WebSockets hold a thread each; a few more serve the page's files meanwhile.
  const CivetServer::Options civet_options = {
      {"document_root", options.root},
      {"enable_directory_listing", "no"},
      {"cgi_pattern", kNothing},
      {"ssi_pattern", kNothing},
      {"num_threads", std::to_string(options.max_connections + 8)},
      {"request_timeout_ms", std::to_string(kWriteTimeoutMs)},
      {"websocket_timeout_ms", std::to_string(kPingIntervalMs)},
      {"enable_websocket_ping_pong", "yes"},
      {"static_file_cache_control", "no-cache"},
      {"max_request_size", "16384"}};
  DDGI_ASSIGN_OR_RETURN(gateway->civet_, CivetServer::start("--web", options.address, options.port,
                                                            civet_options, gateway.get()));
  mg_set_websocket_handler(gateway->civet_->context(), "/ws", &WebGateway::on_connect,
                           &WebGateway::on_ready, &WebGateway::on_data, &WebGateway::on_close,
                           gateway.get());
  mg_set_request_handler(gateway->civet_->context(), "/scene.glb", &WebGateway::on_scene_request,
                         gateway.get());
  LOG_INFO << "web front on port " << gateway->port() << ", files from " << options.root;
  return gateway;
}

WebGateway::~WebGateway() {
  civet_.reset();
}

int WebGateway::on_connect(const mg_connection*, void* self) {
  auto* gateway = static_cast<WebGateway*>(self);
  // Counted once the handshake is done (on_ready), so two handshakes at once may both pass:
  // civetweb's thread pool (max_connections + 8) is the hard bound.
  if (gateway->metrics_.web_connections.load() >= gateway->max_connections_) {
    LOG_WARNING << "web: a WebSocket was refused: " << gateway->max_connections_
                << " are open (--web-max-connections)";
    return 1;  // civetweb closes it
  }
  return 0;
}

void WebGateway::on_ready(mg_connection* connection, void* self) {
  auto* gateway = static_cast<WebGateway*>(self);
  auto send = [connection](bool binary, std::string_view bytes) {
    const int opcode = binary ? MG_WEBSOCKET_OPCODE_BINARY : MG_WEBSOCKET_OPCODE_TEXT;
    return mg_websocket_write(connection, opcode, bytes.data(), bytes.size()) > 0;
  };
  mg_set_user_connection_data(
      connection, new WebConnection(*gateway->stub_, std::move(send), gateway->metrics_));
  ++gateway->metrics_.web_connections;
}

int WebGateway::on_data(mg_connection* connection, int bits, char* data, size_t size, void*) {
  auto* browser = static_cast<WebConnection*>(mg_get_user_connection_data(connection));
  const int opcode = bits & 0xf;
  const bool final_fragment = (bits & 0x80) != 0;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  if (browser == nullptr) return 1;
  if (opcode != MG_WEBSOCKET_OPCODE_TEXT || !final_fragment) {
    browser->refuse("only whole text messages (a WebRequest in JSON) are accepted");
  } else if (size > kMaxTextBytes) {
    browser->refuse("a message of " + std::to_string(size) + " bytes is over the limit of " +
                    std::to_string(kMaxTextBytes));
  } else {
    browser->handle_text(std::string_view(data, size));
  }
  return 1;
}

int WebGateway::on_scene_request(mg_connection* connection, void* self) {
  return serve_scene_download(connection, *static_cast<WebGateway*>(self)->stub_);
}

void WebGateway::on_close(const mg_connection* connection, void* self) {
  auto* gateway = static_cast<WebGateway*>(self);
  auto* browser = static_cast<WebConnection*>(
      mg_get_user_connection_data(const_cast<mg_connection*>(connection)));
  if (browser == nullptr) return;  // the handshake did not finish
  delete browser;                  // ends its stream before the connection goes
  --gateway->metrics_.web_connections;
}

}  // namespace ddgi::service
