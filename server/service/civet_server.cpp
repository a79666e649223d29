#include "service/civet_server.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "core/log.h"

namespace ddgi::service {
namespace {

// civetweb's own messages (bind failures, refused requests) go to our log, not to stderr.
int log_message(const mg_connection*, const char* message) {
  LOG_DEBUG << "civetweb: " << message;
  return 1;
}

}  // namespace

Result<std::unique_ptr<CivetServer>> CivetServer::start(const std::string& flag,
                                                        const std::string& address, int port,
                                                        const Options& options, void* user_data) {
  in_addr parsed{};
  if (inet_pton(AF_INET, address.c_str(), &parsed) != 1) {
    return invalid_argument(flag + "-address '" + address + "' is not an IPv4 address");
  }
  if (port < 0 || port > 65535) {
    return invalid_argument(flag + "-port " + std::to_string(port) + " is out of range [0, 65535]");
  }
  static std::once_flag library;
  std::call_once(library, [] { mg_init_library(MG_FEATURES_WEBSOCKET); });

  std::unique_ptr<CivetServer> server(new CivetServer());
  // Where this process reaches its own port: the address, or loopback for "any".
  server->wake_address_ = parsed;
  if (parsed.s_addr == htonl(INADDR_ANY)) server->wake_address_.s_addr = htonl(INADDR_LOOPBACK);
  const std::string listen = address + ":" + std::to_string(port);
  std::vector<const char*> names_and_values = {"listening_ports", listen.c_str()};
  for (const auto& [name, value] : options) {
    names_and_values.push_back(name.c_str());
    names_and_values.push_back(value.c_str());
  }
  names_and_values.push_back(nullptr);

  mg_callbacks callbacks{};
  callbacks.log_message = &log_message;
  mg_init_data init{};
  init.callbacks = &callbacks;
  init.user_data = user_data;
  init.configuration_options = names_and_values.data();
  char error_text[256] = {};
  unsigned error_code = 0;
  mg_error_data error{};
  error.code = &error_code;
  error.text = error_text;
  error.text_buffer_size = sizeof(error_text);
  server->context_ = mg_start2(&init, &error);
  if (server->context_ == nullptr) {
    return unavailable(flag.substr(2) + " endpoint " + listen + ": " +
                       (error_text[0] != '\0' ? std::string(error_text) : "cannot start"));
  }
  mg_server_port ports[1] = {};
  if (mg_get_server_ports(server->context_, 1, ports) != 1) {
    return unavailable(flag.substr(2) + " endpoint " + listen + ": no listening port");
  }
  server->port_ = ports[0].port;
  return server;
}

CivetServer::~CivetServer() {
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

void CivetServer::wake_accept_loop() const {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port_));
  addr.sin_addr = wake_address_;
  (void)::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
  ::close(fd);
}

}  // namespace ddgi::service
