// A minimal HTTP/1.0 responder for Prometheus scrapes: GET /metrics on its own port, one
// connection at a time, every read bounded by a timeout. Nothing else is served.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "core/result.h"

namespace ddgi::service {

class MetricsHttpServer {
 public:
  // Listens on address:port (port 0 picks a free one, see port()); `body` makes each response.
  static Result<std::unique_ptr<MetricsHttpServer>> start(const std::string& address, int port,
                                                          std::function<std::string()> body);
  ~MetricsHttpServer();
  int port() const { return port_; }

 private:
  MetricsHttpServer() = default;
  void serve();
  void answer(int client);

  int listen_fd_ = -1;
  int port_ = 0;
  std::function<std::string()> body_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ddgi::service
