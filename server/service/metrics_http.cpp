#include "service/metrics_http.h"

#include <civetweb.h>

#include <cstring>

namespace ddgi::service {
namespace {

constexpr const char* kMetricsType = "text/plain; version=0.0.4; charset=utf-8";

void reply(mg_connection* connection, int status, const char* reason, const char* content_type,
           const std::string& body) {
  mg_printf(connection,
            "HTTP/1.1 %d %s\r\nContent-Type: %s\r\nContent-Length: %zu\r\n"
            "Cache-Control: no-store\r\nConnection: close\r\n\r\n",
            status, reason, content_type, body.size());
  mg_write(connection, body.data(), body.size());
}

}  // namespace

Result<std::unique_ptr<MetricsHttpServer>> MetricsHttpServer::start(
    const std::string& address, int port, std::function<std::string()> body) {
  std::unique_ptr<MetricsHttpServer> server(new MetricsHttpServer());
  server->body_ = std::move(body);
  // No document_root: civetweb serves no files; every request reaches handle().
  const CivetServer::Options options = {
      {"num_threads", std::to_string(kWorkerThreads)},
      {"request_timeout_ms", std::to_string(int(kRequestDeadlineSeconds * 1000))},
      {"enable_keep_alive", "no"},
      {"max_request_size", "8192"},
      {"linger_timeout_ms", "0"}};
  DDGI_ASSIGN_OR_RETURN(server->civet_,
                        CivetServer::start("--metrics", address, port, options, server.get()));
  mg_set_request_handler(server->civet_->context(), "/", &MetricsHttpServer::handle, server.get());
  return server;
}

int MetricsHttpServer::handle(mg_connection* connection, void* self) {
  const mg_request_info* request = mg_get_request_info(connection);
  const char* method = request->request_method != nullptr ? request->request_method : "";
  const char* path = request->local_uri != nullptr ? request->local_uri : "";
  if (std::strcmp(method, "GET") != 0) {
    reply(connection, 400, "Bad Request", "text/plain", "expected GET /metrics\n");
    return 400;
  }
  if (std::strcmp(path, "/metrics") != 0) {
    reply(connection, 404, "Not Found", "text/plain", "only /metrics is served here\n");
    return 404;
  }
  reply(connection, 200, "OK", kMetricsType, static_cast<MetricsHttpServer*>(self)->body_());
  return 200;
}

}  // namespace ddgi::service
