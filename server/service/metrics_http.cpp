#include "service/metrics_http.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <mutex>
#include <thread>

#include "core/log.h"

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

// civetweb's own messages (bind failures, refused requests) go to our log, not to stderr.
int log_message(const mg_connection*, const char* message) {
  LOG_DEBUG << "metrics endpoint: " << message;
  return 1;
}

}  // namespace

Result<std::unique_ptr<MetricsHttpServer>> MetricsHttpServer::start(
    const std::string& address, int port, std::function<std::string()> body) {
  in_addr parsed{};
  if (inet_pton(AF_INET, address.c_str(), &parsed) != 1) {
    return invalid_argument("--metrics-address '" + address + "' is not an IPv4 address");
  }
  if (port < 0 || port > 65535) {
    return invalid_argument("--metrics-port " + std::to_string(port) +
                            " is out of range [0, 65535]");
  }
  static std::once_flag library;
  std::call_once(library, [] { mg_init_library(0); });

  std::unique_ptr<MetricsHttpServer> server(new MetricsHttpServer());
  server->body_ = std::move(body);
  // Where this process reaches its own port: the address, or loopback for "any".
  server->wake_address_ = parsed;
  if (parsed.s_addr == htonl(INADDR_ANY)) server->wake_address_.s_addr = htonl(INADDR_LOOPBACK);
  const std::string listen = address + ":" + std::to_string(port);
  const std::string deadline_ms = std::to_string(int(kRequestDeadlineSeconds * 1000));
  const std::string threads = std::to_string(kWorkerThreads);
  // No document_root: civetweb serves no files; every request reaches handle().
  const char* options[] = {"listening_ports",
                           listen.c_str(),
                           "num_threads",
                           threads.c_str(),
                           "request_timeout_ms",
                           deadline_ms.c_str(),
                           "enable_keep_alive",
                           "no",
                           "max_request_size",
                           "8192",
                           "linger_timeout_ms",
                           "0",
                           nullptr};
  mg_callbacks callbacks{};
  callbacks.log_message = &log_message;
  mg_init_data init{};
  init.callbacks = &callbacks;
  init.user_data = server.get();
  init.configuration_options = options;
  char error_text[256] = {};
  unsigned error_code = 0;
  mg_error_data error{};
  error.code = &error_code;
  error.text = error_text;
  error.text_buffer_size = sizeof(error_text);
  server->context_ = mg_start2(&init, &error);
  if (server->context_ == nullptr) {
    return unavailable("metrics endpoint " + listen + ": " +
                       (error_text[0] != '\0' ? std::string(error_text) : "cannot start"));
  }
  mg_set_request_handler(server->context_, "/", &MetricsHttpServer::handle, server.get());
  mg_server_port ports[1] = {};
  if (mg_get_server_ports(server->context_, 1, ports) != 1) {
    return unavailable("metrics endpoint " + listen + ": no listening port");
  }
  server->port_ = ports[0].port;
  return server;
}

MetricsHttpServer::~MetricsHttpServer() {
  if (context_ == nullptr) return;
  // mg_stop waits for the workers (no handler runs once it returns) and for civetweb's accept
  // loop, which polls in 2-second quanta: a connection to the port wakes it at once, so the
  // server's shutdown is not held up by up to 2 s.
  std::atomic<bool> stopped{false};
  std::thread stopper([this, &stopped] {
    mg_stop(context_);
    stopped = true;
  });
  while (!stopped) {
    wake_accept_loop();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  stopper.join();
}

void MetricsHttpServer::wake_accept_loop() const {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port_));
  addr.sin_addr = wake_address_;
  (void)::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
  ::close(fd);
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
