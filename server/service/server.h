// The gRPC server around RenderServiceImpl: listening socket (optionally TLS), message limits,
// keepalive, the health service, reflection, the metrics endpoint, and an orderly shutdown.
// ddgi-server's main() and the service tests both start it through here.
#pragma once

#include <grpcpp/grpcpp.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "core/result.h"
#include "service/frame_encoder.h"
#include "service/limits.h"
#include "service/metrics.h"
#include "service/metrics_http.h"
#include "service/render_service.h"
#include "service/session_budget.h"
#include "service/session_registry.h"
#include "service/submit_pacer.h"
#include "service/web_gateway.h"
#include "vk/context.h"

namespace ddgi::service {

struct ServerOptions {
  std::string listen = "0.0.0.0:50051";  // host:port; port 0 picks a free one (see port())
  std::string scene_root;                // the scene library folder
  ServiceLimits limits;
  bool reflection = true;
  std::string tls_cert_file;  // PEM; both or neither
  std::string tls_key_file;
  std::string auth_token;  // empty: no auth
  int metrics_port = -1;   // -1: no metrics endpoint; 0: a free port
  std::string metrics_address = "0.0.0.0";
  WebOptions web;  // the browser client's front (off unless web.port >= 0)
  unsigned encode_threads = 2;
  std::chrono::milliseconds shutdown_grace{5000};  // for streams and frame loops to end
  // GPU work (ms) a session leaves queued when it submits its next frames (service/
  // submit_pacer.h), in [0, kMaxSubmitAheadMs]: less lowers the latency from a command to its
  // frame by as much, too little lets the GPU run dry between frames when the loop wakes late.
  // kDefaultSubmitAheadMs (0.5) says why its default; 1000: no pacing (--submit-ahead-ms).
  double submit_ahead_ms = kDefaultSubmitAheadMs;
  // A session's configuration (service/session_budget.h): the budget of sessions that set no
  // budget_ms (--budget-ms), how a calibration measures (its frame: --budget-frame), where
  // calibrations are kept (--budget-cache; empty: memory only).
  double default_budget_ms = tools::kDefaultBudgetMs;
  tools::CalibrationOptions budget_calibration;
  std::string budget_cache_dir;
  // Whether scenes are calibrated in the background (--calibration). ddgi-server turns it on on
  // a GPU (--calibration auto, its default); off here, so that a test or an embedder that did
  // not ask pays no calibration. `calibration_off_reason` is what sessions report then.
  bool calibration = false;
  std::string calibration_off_reason = "the server calibrates no scene (--calibration off)";
  // The share of GPU time a calibration may take, (0, 1] (--calibration-share).
  double calibration_share = kDefaultCalibrationShare;
  // Runs once when the GPU device is lost (vk::Context::device_lost), after the server turned
  // health NOT_SERVING, refused new work and ended every session with the loss as their status;
  // on the thread that saw the loss, which it must not block. ddgi-server exits then, so its
  // supervisor restarts it on a fresh device.
  std::function<void(const Error& why)> on_device_lost;
  // Test-only: no flag sets it. See SessionRegistry::SessionLoadedHook.
  SessionRegistry::SessionLoadedHook test_session_loaded_hook;
};

class Server {
 public:
  static Result<std::unique_ptr<Server>> start(vk::Context& context, ServerOptions options);
  ~Server();

  int port() const { return port_; }
  int metrics_port() const { return metrics_http_ ? metrics_http_->port() : -1; }
  int web_port() const { return web_ ? web_->port() : -1; }
  Metrics& metrics() { return metrics_; }
  // A channel to this server inside the process (no socket): the request fuzzer's.
  std::shared_ptr<grpc::Channel> in_process_channel();
  SessionRegistry& sessions() { return *sessions_; }

  // Health NOT_SERVING, new sessions and streams refused, sessions closed (streams end with OK),
  // then the gRPC server stops; bounded by shutdown_grace (plus one second for gRPC). Returns
  // false when something did not end in time.
  bool shutdown();

 private:
  explicit Server(vk::Context& context) : context_(context) {}
  // The device-lost handler (ServerOptions::on_device_lost says what it does).
  void device_lost(const Error& why);

  vk::Context& context_;
  ServerOptions options_;
  Metrics metrics_;
  std::unique_ptr<FrameEncoder> encoder_;
  BudgetService budget_;  // before sessions_: their loops use it until they end
  std::unique_ptr<SessionRegistry> sessions_;
  std::unique_ptr<RenderServiceImpl> service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<MetricsHttpServer> metrics_http_;
  std::unique_ptr<WebGateway> web_;
  int port_ = 0;
  bool shut_down_ = false;
};

}  // namespace ddgi::service
