// The web front of ddgi-server (docs/web.md): on its own port, civetweb serves the web
// client's static files (web/) and a WebSocket per browser at /ws (web.proto). Each browser
// is a WebConnection whose calls go to the RenderService over an in-process channel with the
// browser's token, so auth, limits, validation and RPC metrics are exactly the gRPC API's;
// its frames come from StreamFrames through a latest-frame-wins slot (web_frame_stream.h).
// GET /scene.glb?session=ID downloads a session's scene (web_scene_download.h).
// No HTTP or WebSocket parsing is ours: civetweb does both.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "core/result.h"
#include "ddgi/v1/render_service.grpc.pb.h"
#include "service/civet_server.h"
#include "service/metrics.h"

struct mg_connection;

namespace ddgi::service {

struct WebOptions {
  // -1: no web front; 0: a free port (see WebGateway::port()). 1..65535.
  int port = -1;
  std::string address = "0.0.0.0";  // IPv4 address to listen on
  // The web client's files (the repo's web/); must hold index.html.
  std::string root;
  // WebSockets open at once, 1..1024: each holds one of civetweb's threads for its lifetime
  // (and two more while it streams). More are refused at the handshake.
  int max_connections = 32;
};

class WebGateway {
 public:
  // Largest text message a browser may send; commands are far smaller.
  static constexpr size_t kMaxTextBytes = 1 << 20;
  // A write to a browser that takes longer than this ends its connection.
  static constexpr int kWriteTimeoutMs = 10000;
  // With no message from the browser for this long, civetweb pings it (and closes the
  // connection after several unanswered pings).
  static constexpr int kPingIntervalMs = 10000;

  static Result<std::unique_ptr<WebGateway>> start(const WebOptions& options,
                                                   std::shared_ptr<grpc::Channel> channel,
                                                   Metrics& metrics);
  // Closes every WebSocket (their streams end) and stops serving.
  ~WebGateway();
  WebGateway(const WebGateway&) = delete;
  WebGateway& operator=(const WebGateway&) = delete;

  int port() const { return civet_->port(); }

 private:
  WebGateway(std::shared_ptr<grpc::Channel> channel, Metrics& metrics, int max_connections);
  static int on_connect(const mg_connection* connection, void* self);
  static void on_ready(mg_connection* connection, void* self);
  static int on_data(mg_connection* connection, int bits, char* data, size_t size, void* self);
  static void on_close(const mg_connection* connection, void* self);
  static int on_scene_request(mg_connection* connection, void* self);

  std::unique_ptr<v1::RenderService::Stub> stub_;
  Metrics& metrics_;
  const int max_connections_;
  std::unique_ptr<CivetServer> civet_;  // last: stopped first, while the rest is still there
};

}  // namespace ddgi::service
