// One civetweb context (Debian's libcivetweb) listening on an IPv4 address and port, shared by
// the service's two HTTP fronts: the Prometheus endpoint (metrics_http.h) and the web client's
// files and WebSockets (web_gateway.h). It owns what both need alike: address and port
// validation with errors that name the flag, civetweb's log routed to ours, the port actually
// bound (port 0 picks a free one), and a stop that does not wait out civetweb's accept poll.
#pragma once

#include <netinet/in.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/result.h"

struct mg_context;

namespace ddgi::service {

class CivetServer {
 public:
  using Options = std::vector<std::pair<std::string, std::string>>;

  // Listens on address:port. `flag` names the endpoint's flags in errors ("--metrics" gives
  // "--metrics-address", "--metrics-port"); `options` are civetweb's configuration options
  // besides listening_ports; `user_data` is what mg_get_user_data returns in handlers.
  static Result<std::unique_ptr<CivetServer>> start(const std::string& flag,
                                                    const std::string& address, int port,
                                                    const Options& options, void* user_data);
  // Stops civetweb: no handler runs once it returns.
  ~CivetServer();
  CivetServer(const CivetServer&) = delete;
  CivetServer& operator=(const CivetServer&) = delete;

  mg_context* context() const { return context_; }
  int port() const { return port_; }

 private:
  CivetServer() = default;
  void wake_accept_loop() const;

  mg_context* context_ = nullptr;
  int port_ = 0;
  in_addr wake_address_{};
};

}  // namespace ddgi::service
