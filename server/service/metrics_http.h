// The Prometheus endpoint: GET /metrics over HTTP/1.x on its own port, served by civetweb
// (Debian's libcivetweb, which also speaks WebSocket for a later browser client). A pool of
// worker threads takes connections, so a slow or stalled client holds one worker, never the
// endpoint: a scrape is answered while others trickle. Each request must arrive whole within
// kRequestDeadlineSeconds of its start (civetweb's request_timeout_ms is measured from the
// start of the request, not per read) and its reply is written under the same bound; keep-alive
// is off, so a connection carries one request. Other paths are 404, other methods 400.
#pragma once

#include <netinet/in.h>

#include <functional>
#include <memory>
#include <string>

#include "core/result.h"

struct mg_connection;
struct mg_context;

namespace ddgi::service {

class MetricsHttpServer {
 public:
  // A request must arrive whole within this many seconds, its reply be taken up as quickly.
  static constexpr double kRequestDeadlineSeconds = 5.0;
  // Connections served at once; more wait (for at most the deadline of those ahead of them).
  static constexpr int kWorkerThreads = 16;

  // Listens on address:port (an IPv4 address; port 0 picks a free one, see port()); `body`
  // makes each response and may be called from several threads at once.
  static Result<std::unique_ptr<MetricsHttpServer>> start(const std::string& address, int port,
                                                          std::function<std::string()> body);
  ~MetricsHttpServer();
  MetricsHttpServer(const MetricsHttpServer&) = delete;
  MetricsHttpServer& operator=(const MetricsHttpServer&) = delete;

  int port() const { return port_; }

 private:
  MetricsHttpServer() = default;
  static int handle(mg_connection* connection, void* self);
  void wake_accept_loop() const;

  mg_context* context_ = nullptr;
  int port_ = 0;
  in_addr wake_address_{};
  std::function<std::string()> body_;
};

}  // namespace ddgi::service
