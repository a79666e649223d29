#include "service/server.h"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/impl/server_builder_option.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/log.h"

namespace ddgi::service {
namespace {

Result<std::string> read_file(const std::string& path, const char* what) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return not_found(std::string("cannot read the ") + what + " " + path);
  std::ostringstream text;
  text << file.rdbuf();
  if (text.str().empty())
    return invalid_argument(std::string("the ") + what + " " + path + " is empty");
  return text.str();
}

// grpc++_reflection adds its plugin to every ServerBuilder as soon as the library is loaded (a
// static initializer), so turning reflection off means taking the plugin out of the builder.
class WithoutReflection : public grpc::ServerBuilderOption {
 public:
  void UpdateArguments(grpc::ChannelArguments*) override {}
  void UpdatePlugins(std::vector<std::unique_ptr<grpc::ServerBuilderPlugin>>* plugins) override {
    const std::string reflection = grpc::reflection::ProtoServerReflectionPlugin().name();
    std::erase_if(*plugins, [&](const auto& plugin) { return plugin->name() == reflection; });
  }
};

}  // namespace

Result<std::unique_ptr<Server>> Server::start(vk::Context& context, ServerOptions options) {
  DDGI_TRY(validate(options.limits));
  DDGI_TRY(tools::validate(options.budget_calibration));
  if (const Status budget = tools::check_budget_ms(options.default_budget_ms); !budget.ok()) {
    return invalid_argument("--budget-ms: " + budget.error().message);
  }
  DDGI_TRY(check_calibration_share(options.calibration_share));
  DDGI_TRY(check_submit_ahead_ms(options.submit_ahead_ms));
  if (options.tls_cert_file.empty() != options.tls_key_file.empty()) {
    return invalid_argument("TLS needs both --tls-cert and --tls-key");
  }
  std::unique_ptr<Server> server(new Server(context));
  server->options_ = options;
  server->encoder_ = std::make_unique<FrameEncoder>(options.encode_threads, server->metrics_);
  SessionEnv env;
  env.context = &context;
  env.limits = &server->options_.limits;
  env.metrics = &server->metrics_;
  env.encoder = server->encoder_.get();
  env.submit_ahead = SubmitPacer::Millis(options.submit_ahead_ms);
  server->budget_.default_ms = options.default_budget_ms;
  server->budget_.calibration = options.budget_calibration;
  server->budget_.off_reason = options.calibration_off_reason;
  if (options.calibration) {
    server->budget_.calibrator = std::make_unique<Calibrator>(options.calibration_share);
  }
  if (const Status kept = server->budget_.cache.persist_in(options.budget_cache_dir); !kept.ok()) {
    return invalid_argument("--budget-cache: " + kept.error().message);
  }
  env.budget = &server->budget_;
  server->sessions_ = std::make_unique<SessionRegistry>(env, options.test_session_loaded_hook);
  server->service_ = std::make_unique<RenderServiceImpl>(
      context, options.limits, SceneLibrary(options.scene_root), BearerAuth(options.auth_token),
      server->metrics_, *server->sessions_);

  std::shared_ptr<grpc::ServerCredentials> credentials = grpc::InsecureServerCredentials();
  if (!options.tls_cert_file.empty()) {
    DDGI_ASSIGN_OR_RETURN(const std::string cert,
                          read_file(options.tls_cert_file, "TLS certificate"));
    DDGI_ASSIGN_OR_RETURN(const std::string key, read_file(options.tls_key_file, "TLS key"));
    grpc::SslServerCredentialsOptions ssl;
    ssl.pem_key_cert_pairs.push_back({key, cert});
    credentials = grpc::SslServerCredentials(ssl);
  }

  grpc::EnableDefaultHealthCheckService(true);
  if (options.reflection) grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(options.listen, credentials, &server->port_);
  builder.RegisterService(server->service_.get());
  if (!options.reflection) builder.SetOption(std::make_unique<WithoutReflection>());
  builder.SetMaxReceiveMessageSize(static_cast<int>(max_receive_bytes(options.limits)));
  builder.SetMaxSendMessageSize(static_cast<int>(options.limits.max_message_bytes));
  // Keepalive: find dead peers of idle streams within ~30 s, and let clients ping idle
  // connections (every 10 s at most) without being cut off.
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, 20000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 10000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS, 10000);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA, 0);
  // A connection that sends nothing for an hour is dropped; streams in progress are not idle.
  builder.AddChannelArgument(GRPC_ARG_MAX_CONNECTION_IDLE_MS, 3600 * 1000);
  server->server_ = builder.BuildAndStart();
  if (!server->server_ || server->port_ == 0) {
    return unavailable("cannot listen on " + options.listen +
                       " (address in use, or not host:port?)");
  }
  server->server_->GetHealthCheckService()->SetServingStatus(true);
  context.set_device_lost_handler(
      [raw = server.get()](const Error& why) { raw->device_lost(why); });

  Metrics* metrics = &server->metrics_;
  metrics->add_gauge("ddgi_gpu_memory_bytes", "GPU memory held by all sessions.",
                     [&context] { return double(context.allocated_bytes()); });
  metrics->add_gauge("ddgi_gpu_memory_budget_bytes", "The GPU memory budget (0: the device's).",
                     [&context] { return double(context.memory_budget()); });
  metrics->add_gauge("ddgi_gpu_device_lost", "1 once the GPU device was lost (restart needed).",
                     [&context] { return context.device_lost() ? 1.0 : 0.0; });
  if (options.metrics_port >= 0) {
    DDGI_ASSIGN_OR_RETURN(
        server->metrics_http_,
        MetricsHttpServer::start(options.metrics_address, options.metrics_port,
                                 [metrics] { return metrics->prometheus_text(); }));
  }
  if (options.web.port >= 0) {
    DDGI_ASSIGN_OR_RETURN(server->web_,
                          WebGateway::start(options.web, server->in_process_channel(), *metrics));
    if (!options.tls_cert_file.empty()) {
      LOG_WARNING << "the web front serves plain HTTP while gRPC uses TLS: browsers' tokens and "
                     "frames cross in clear text; put a TLS proxy in front of --web-port or "
                     "bind it to 127.0.0.1 (docs/web.md)";
    }
  }
  LOG_INFO << "ddgi-server listening port=" << server->port_
           << " tls=" << (options.tls_cert_file.empty() ? "off" : "on")
           << " auth=" << (options.auth_token.empty() ? "off" : "on")
           << " reflection=" << (options.reflection ? "on" : "off")
           << " metrics_port=" << server->metrics_port() << " web_port=" << server->web_port()
           << " scene_root=" << options.scene_root;
  return server;
}

bool Server::shutdown() {
  if (shut_down_) return true;
  shut_down_ = true;
  const auto start = std::chrono::steady_clock::now();
  LOG_INFO << "shutting down: health NOT_SERVING, closing sessions";
  server_->GetHealthCheckService()->SetServingStatus(false);
  service_->refuse_new_work("the server is shutting down");
  sessions_->close_all();
  context_.set_device_lost_handler(nullptr);
  bool in_time = sessions_->wait_for_loops(options_.shutdown_grace);
  web_.reset();  // browsers' streams have ended with their sessions; their sockets close
  if (!in_time) {
    LOG_WARNING << "frame loops still running after the shutdown grace period";
  }
  if (in_time) {
    encoder_.reset();  // encodes what is queued, so every RenderFrame waiting gets its answer
  } else {
    (void)encoder_.release();  // a stuck loop may still use it; the process is about to exit
  }
  // Our streams have ended by now; what is left are calls like health watches and unary calls
  // that fail at once: a second is plenty before gRPC cancels them.
  const auto left = options_.shutdown_grace - (std::chrono::steady_clock::now() - start);
  const auto wait = std::clamp<std::chrono::steady_clock::duration>(
      left, std::chrono::milliseconds(100), std::chrono::milliseconds(1000));
  const auto deadline = std::chrono::system_clock::now() + wait;
  server_->Shutdown(deadline);
  server_->Wait();
  metrics_http_.reset();
  LOG_INFO << "shut down in "
           << std::chrono::duration_cast<std::chrono::milliseconds>(
                  std::chrono::steady_clock::now() - start)
                  .count()
           << " ms";
  return in_time;
}

std::shared_ptr<grpc::Channel> Server::in_process_channel() {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(static_cast<int>(options_.limits.max_message_bytes));
  return server_->InProcessChannel(args);
}

void Server::device_lost(const Error& why) {
  LOG_ERROR << why.message << ": ending every session";
  server_->GetHealthCheckService()->SetServingStatus(false);
  service_->refuse_new_work(why.message);
  sessions_->close_all(why);
  if (options_.on_device_lost) options_.on_device_lost(why);
}

Server::~Server() {
  if (server_) shutdown();
}

}  // namespace ddgi::service
