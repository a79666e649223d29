// The Prometheus endpoint: GET /metrics over HTTP/1.x on its own port, served by civetweb
// (civet_server.h, shared with the web client's front). A pool of
// worker threads takes connections, so a slow or stalled client holds one worker, never the
// endpoint: a scrape is answered while others trickle. Each request must arrive whole within
// kRequestDeadlineSeconds of its start (civetweb's request_timeout_ms is measured from the
// start of the request, not per read) and its reply is written under the same bound; keep-alive
// is off, so a connection carries one request. Other paths are 404, other methods 400.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "core/result.h"
#include "service/civet_server.h"

struct mg_connection;

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
  MetricsHttpServer(const MetricsHttpServer&) = delete;
  MetricsHttpServer& operator=(const MetricsHttpServer&) = delete;

  int port() const { return civet_->port(); }

 private:
  MetricsHttpServer() = default;
  static int handle(mg_connection* connection, void* self);

  std::function<std::string()> body_;
  std::unique_ptr<CivetServer> civet_;  // last: stopped first, while body_ is still there
};

}  // namespace ddgi::service
