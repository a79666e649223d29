// ddgi-server: the DDGI render service (proto/ddgi/v1/render_service.proto, docs/service.md).
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include "core/flags.h"
#include "core/log.h"
#include "service/auth.h"
#include "service/process_memory.h"
#include "service/server.h"
#include "vk/context.h"

namespace ddgi::service {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-server [flags]

Serves the DDGI render service over gRPC (docs/service.md). Stops on SIGTERM or SIGINT:
health turns NOT_SERVING, streams end with OK, the process exits within --shutdown-grace.
If the GPU device is lost, every session ends with UNAVAILABLE naming the loss, health turns
NOT_SERVING and the process exits with status 1, for its supervisor to restart it.

  --listen HOST:PORT        where to listen; port 0 picks a free one  [0.0.0.0:50051]
  --port-file FILE          write the port listened on to FILE (for scripts)
  --scene-root DIR          the scene library folder                  [the repo's scenes/]
  --max-sessions N          [8]       --max-views-per-session N  [16]
  --max-one-off-frames N    one-off RenderFrame calls in flight per session  [8]
  --max-width N             [3840]    --max-height N             [2160]
  --max-message-bytes N     largest message sent or received       [16777216]
  --max-upload-bytes N      largest uploaded .glb                  [67108864]
  --max-query-points N      [65536]   --max-lights N             [256]
  --max-fps X               frames per second per session, at most [60]
  --max-warmup-updates N    [1024]
  --gpu-memory-budget N     bytes of GPU memory for all sessions; K/M/G suffixes  [device size]
  --no-reflection           turn off gRPC server reflection
  --tls-cert FILE --tls-key FILE   serve TLS with this PEM certificate chain and key
  --auth-token-file FILE    require "authorization: Bearer <token>" (token read from FILE)
  --metrics-port N          Prometheus metrics at http://ADDRESS:N/metrics; -1: off  [9464]
  --metrics-address A       IPv4 address of the metrics endpoint    [0.0.0.0]
  --web-port N              the browser client at http://ADDRESS:N/ (docs/web.md); -1: off  [-1]
  --web-address A           IPv4 address of the web front            [0.0.0.0]
  --web-root DIR            the web client's files                   [the repo's web/]
  --web-max-connections N   browsers connected at once, 1..1024      [32]
  --encode-threads N        JPEG encoder threads, 1..64; also the most  [2]
                            strips one frame is compressed in at once
  --shutdown-grace S        seconds for streams and sessions to end  [5]
  --submit-ahead-ms MS      GPU work a session leaves queued when it submits its next frame:
                            less is less latency from a command to its frame, too little
                            idles the GPU; 1000: submit at once (no pacing)  [0.5]
  --budget-ms MS            GPU ms per frame of a session that sets no budget_ms: the rule
                            picks the configuration of lowest measured error (FLIP, plus light
                            beyond 5% of the path tracer's) that fits; the cheapest where none
                            does (docs/service.md, "The session's configuration")  [4]
  --budget-frame WxH        the frame a budget pays for               [1920x1080]
  --calibration M           auto | on | off: measure each scene's candidate configurations in
                            the background while its sessions stream the static default, then
                            switch them to the choice; auto: on a GPU, off on a CPU device
                            (lavapipe), where it takes minutes per scene  [auto]
  --calibration-share X     the share of GPU time a calibration may take, (0, 1]  [0.333]
  --budget-cache DIR        where calibrations are kept, so a restarted server does not
                            calibrate a scene again; none: memory only
                            [$XDG_CACHE_HOME/ddgi, else $HOME/.cache/ddgi]
  --device NAME             Vulkan device whose name contains NAME
  --backend B               auto | query | pipeline                  [auto]
  --validation              Vulkan validation layers (any message is logged)
  --log-level L             debug | info | warning | error           [info]
)";

// The calibration cache's default: $XDG_CACHE_HOME/ddgi, else $HOME/.cache/ddgi, else none
// (memory only) where neither is set.
std::string default_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    return std::string(xdg) + "/ddgi";
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return std::string(home) + "/.cache/ddgi";
  }
  return "";
}

// The default where it can be made; else memory only, with a warning (a read-only home in a
// container must not stop the server; a --budget-cache given explicitly must be usable).
std::string usable_default_cache_dir() {
  const std::string dir = default_cache_dir();
  std::error_code error;
  if (!dir.empty()) std::filesystem::create_directories(dir, error);
  if (dir.empty() || error || ::access(dir.c_str(), W_OK) != 0) {
    LOG_WARNING << "calibrations kept in memory only: the default cache folder '" << dir
                << "' cannot be written (--budget-cache DIR names another)";
    return "";
  }
  return dir;
}

std::string default_web_root() {
#ifdef DDGI_DEFAULT_WEB_ROOT
  return DDGI_DEFAULT_WEB_ROOT;
#else
  return "web";
#endif
}

std::string default_scene_root() {
#ifdef DDGI_DEFAULT_SCENE_ROOT
  return DDGI_DEFAULT_SCENE_ROOT;
#else
  return "scenes";
#endif
}

// "512M", "2G", "1048576": bytes.
Result<uint64_t> parse_bytes(const std::string& text, const std::string& flag) {
  if (text.empty()) return invalid_argument(flag + " is empty");
  uint64_t scale = 1;
  std::string digits = text;
  const char last = text.back();
  if (last == 'K' || last == 'k') scale = 1ull << 10;
  if (last == 'M' || last == 'm') scale = 1ull << 20;
  if (last == 'G' || last == 'g') scale = 1ull << 30;
  if (scale != 1) digits.pop_back();
  DDGI_ASSIGN_OR_RETURN(const int64_t value, parse_int(digits, flag));
  if (value < 0 || uint64_t(value) > (1ull << 50) / scale) {
    return invalid_argument(flag + " must be in [0, 1 PiB] (got " + text + ")");
  }
  return uint64_t(value) * scale;
}

Result<Flags> parse_flags(int argc, char** argv) {
  return Flags::parse(argc, argv,
                      {"listen",
                       "port-file",
                       "scene-root",
                       "max-sessions",
                       "max-views-per-session",
                       "max-one-off-frames",
                       "max-width",
                       "max-height",
                       "max-message-bytes",
                       "max-upload-bytes",
                       "max-query-points",
                       "max-lights",
                       "max-fps",
                       "max-warmup-updates",
                       "gpu-memory-budget",
                       "tls-cert",
                       "tls-key",
                       "auth-token-file",
                       "metrics-port",
                       "metrics-address",
                       "web-port",
                       "web-address",
                       "web-root",
                       "web-max-connections",
                       "encode-threads",
                       "shutdown-grace",
                       "submit-ahead-ms",
                       "budget-ms",
                       "budget-frame",
                       "budget-cache",
                       "calibration",
                       "calibration-share",
                       "device",
                       "backend",
                       "log-level"},
                      {"no-reflection", "validation", "help"});
}

Status apply_log_level(const Flags& flags) {
  DDGI_ASSIGN_OR_RETURN(const std::string level_text, flags.get_string("log-level", "info"));
  LogLevel level;
  if (!parse_log_level(level_text, &level)) {
    return invalid_argument("--log-level must be debug, info, warning, error or off");
  }
  set_log_level(level);
  return ok_status();
}

// --max-*, --gpu-memory-budget, validated.
Result<ServiceLimits> service_limits(const Flags& flags) {
  ServiceLimits l;
  auto get_u32 = [&](const char* name, uint32_t fallback, int64_t max) -> Result<uint32_t> {
    DDGI_ASSIGN_OR_RETURN(const int64_t value, flags.get_int(name, fallback, 0, max));
    return static_cast<uint32_t>(value);
  };
  DDGI_ASSIGN_OR_RETURN(l.max_sessions, get_u32("max-sessions", l.max_sessions, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(l.max_views_per_session,
                        get_u32("max-views-per-session", l.max_views_per_session, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(l.max_one_off_frames,
                        get_u32("max-one-off-frames", l.max_one_off_frames, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(l.max_width, get_u32("max-width", l.max_width, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(l.max_height, get_u32("max-height", l.max_height, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(l.max_query_points,
                        get_u32("max-query-points", l.max_query_points, 1 << 30));
  DDGI_ASSIGN_OR_RETURN(l.max_lights, get_u32("max-lights", l.max_lights, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(l.max_warmup_updates,
                        get_u32("max-warmup-updates", l.max_warmup_updates, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(l.max_fps, flags.get_double("max-fps", l.max_fps, 0.0, 1e6));
  DDGI_ASSIGN_OR_RETURN(const std::string message_bytes,
                        flags.get_string("max-message-bytes", std::to_string(l.max_message_bytes)));
  DDGI_ASSIGN_OR_RETURN(l.max_message_bytes, parse_bytes(message_bytes, "--max-message-bytes"));
  DDGI_ASSIGN_OR_RETURN(const std::string upload_bytes,
                        flags.get_string("max-upload-bytes", std::to_string(l.max_upload_bytes)));
  DDGI_ASSIGN_OR_RETURN(l.max_upload_bytes, parse_bytes(upload_bytes, "--max-upload-bytes"));
  DDGI_ASSIGN_OR_RETURN(const std::string budget, flags.get_string("gpu-memory-budget", "0"));
  DDGI_ASSIGN_OR_RETURN(l.gpu_memory_budget_bytes, parse_bytes(budget, "--gpu-memory-budget"));
  DDGI_TRY(validate(l));
  return l;
}

Result<ServerOptions> server_options(const Flags& flags) {
  ServerOptions options;
  DDGI_ASSIGN_OR_RETURN(options.listen, flags.get_string("listen", options.listen));
  DDGI_ASSIGN_OR_RETURN(options.scene_root, flags.get_string("scene-root", default_scene_root()));
  DDGI_ASSIGN_OR_RETURN(options.limits, service_limits(flags));
  options.reflection = !flags.has("no-reflection");
  DDGI_ASSIGN_OR_RETURN(options.tls_cert_file, flags.get_string("tls-cert", ""));
  DDGI_ASSIGN_OR_RETURN(options.tls_key_file, flags.get_string("tls-key", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string token_file, flags.get_string("auth-token-file", ""));
  if (!token_file.empty()) {
    DDGI_ASSIGN_OR_RETURN(options.auth_token, read_token_file(token_file));
  }
  DDGI_ASSIGN_OR_RETURN(const int64_t metrics_port, flags.get_int("metrics-port", 9464, -1, 65535));
  options.metrics_port = static_cast<int>(metrics_port);
  DDGI_ASSIGN_OR_RETURN(options.metrics_address,
                        flags.get_string("metrics-address", options.metrics_address));
  DDGI_ASSIGN_OR_RETURN(const int64_t web_port, flags.get_int("web-port", -1, -1, 65535));
  options.web.port = static_cast<int>(web_port);
  DDGI_ASSIGN_OR_RETURN(options.web.address, flags.get_string("web-address", options.web.address));
  DDGI_ASSIGN_OR_RETURN(options.web.root, flags.get_string("web-root", default_web_root()));
  DDGI_ASSIGN_OR_RETURN(const int64_t web_connections,
                        flags.get_int("web-max-connections", options.web.max_connections, 1, 1024));
  options.web.max_connections = static_cast<int>(web_connections);
  DDGI_ASSIGN_OR_RETURN(const int64_t encode_threads, flags.get_int("encode-threads", 2, 1, 64));
  options.encode_threads = static_cast<unsigned>(encode_threads);
  DDGI_ASSIGN_OR_RETURN(const double grace, flags.get_double("shutdown-grace", 5.0, 0.1, 600.0));
  options.shutdown_grace = std::chrono::milliseconds(static_cast<int64_t>(grace * 1000.0));
  DDGI_ASSIGN_OR_RETURN(
      options.submit_ahead_ms,
      flags.get_double("submit-ahead-ms", options.submit_ahead_ms, 0.0, kMaxSubmitAheadMs));
  DDGI_ASSIGN_OR_RETURN(
      options.default_budget_ms,
      flags.get_double("budget-ms", options.default_budget_ms, 0.0, tools::kMaxBudgetMs));
  DDGI_ASSIGN_OR_RETURN(options.calibration_share,
                        flags.get_double("calibration-share", options.calibration_share, 0.0, 1.0));
  DDGI_ASSIGN_OR_RETURN(const std::string frame, flags.get_string("budget-frame", "1920x1080"));
  const std::vector<std::string> sides = split(frame, 'x');
  if (sides.size() != 2) return invalid_argument("--budget-frame '" + frame + "' is not WxH");
  DDGI_ASSIGN_OR_RETURN(const int64_t width, parse_int(sides[0], "--budget-frame width"));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, parse_int(sides[1], "--budget-frame height"));
  if (width < 16 || width > 16384 || height < 16 || height > 16384) {
    return invalid_argument("--budget-frame must be 16..16384 pixels each way (got " + frame + ")");
  }
  options.budget_calibration.width = static_cast<uint32_t>(width);
  options.budget_calibration.height = static_cast<uint32_t>(height);
  DDGI_ASSIGN_OR_RETURN(const std::string cache, flags.get_string("budget-cache", ""));
  options.budget_cache_dir = cache == "none" ? ""
                             : cache.empty() ? usable_default_cache_dir()
                                             : cache;
  return options;
}

// --calibration: on or off as given; nothing for auto (decided by the device).
Result<std::optional<bool>> calibration_mode(const Flags& flags) {
  DDGI_ASSIGN_OR_RETURN(const std::string mode, flags.get_string("calibration", "auto"));
  if (mode == "auto") return std::optional<bool>();
  if (mode == "on" || mode == "off") return std::optional<bool>(mode == "on");
  return invalid_argument("--calibration must be auto, on or off (got '" + mode + "')");
}

Result<vk::ContextOptions> context_options(const Flags& flags, uint64_t memory_budget_bytes) {
  vk::ContextOptions options;
  options.validation = flags.has("validation");
  DDGI_ASSIGN_OR_RETURN(options.device_filter, flags.get_string("device", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string backend_text, flags.get_string("backend", "auto"));
  DDGI_ASSIGN_OR_RETURN(options.backend, vk::parse_backend(backend_text));
  options.memory_budget_bytes = memory_budget_bytes;
  return options;
}

// The GPU device was lost (ServerOptions::on_device_lost): the handler sets the flag, then sends
// the signal that wakes the main thread, which shuts the server down and exits non-zero.
constexpr int kDeviceLostSignal = SIGUSR1;
std::atomic<bool> g_device_lost{false};

// Signals go to one thread that waits for them; every other thread (gRPC's, the frame loops)
// inherits the blocked mask, so no handler ever runs inside a lock. Call before any thread starts.
sigset_t block_stop_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, kDeviceLostSignal);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

void write_port_file(const std::string& path, int port) {
  std::ofstream out(path + ".tmp");
  out << port << "\n";
  out.close();
  std::rename((path + ".tmp").c_str(), path.c_str());  // readers never see half
}

// Waits for SIGTERM or SIGINT, or for the GPU device to be lost, then shuts `server` down;
// exits the process (code 3) when that takes longer than the grace period allows.
void serve_until_stopped(Server& server, const sigset_t& signals,
                         std::chrono::milliseconds shutdown_grace) {
  int signal_number = 0;
  do {
    sigwait(&signals, &signal_number);
  } while (signal_number == kDeviceLostSignal && !g_device_lost);  // not ours: ignored
  LOG_INFO << "received "
           << (signal_number == SIGTERM  ? "SIGTERM"
               : signal_number == SIGINT ? "SIGINT"
                                         : "the device-lost signal");
  // Whatever happens below, the process is gone a little after the grace period.
  const auto hard_limit = shutdown_grace + std::chrono::seconds(5);
  std::thread([hard_limit] {
    std::this_thread::sleep_for(hard_limit);
    std::fprintf(stderr, "ddgi-server: shutdown took too long, exiting\n");
    _exit(3);
  }).detach();
  if (!server.shutdown()) {
    std::fprintf(stderr, "ddgi-server: sessions did not end in time, exiting without cleanup\n");
    _exit(3);
  }
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(const Flags flags, parse_flags(argc, argv));
  if (flags.has("help")) {
    std::fputs(kUsage, stdout);
    return ok_status();
  }
  if (!flags.positional().empty()) {
    return invalid_argument("unexpected argument '" + flags.positional()[0] + "' (see --help)");
  }
  DDGI_TRY(apply_log_level(flags));
  DDGI_ASSIGN_OR_RETURN(ServerOptions options, server_options(flags));
  options.on_device_lost = [](const Error&) {
    g_device_lost = true;
    kill(getpid(), kDeviceLostSignal);  // wakes serve_until_stopped
  };
  DDGI_ASSIGN_OR_RETURN(const std::optional<bool> calibration, calibration_mode(flags));
  DDGI_ASSIGN_OR_RETURN(const std::string port_file, flags.get_string("port-file", ""));
  DDGI_ASSIGN_OR_RETURN(const vk::ContextOptions vulkan,
                        context_options(flags, options.limits.gpu_memory_budget_bytes));
  const sigset_t signals = block_stop_signals();

  DDGI_ASSIGN_OR_RETURN(auto context, vk::Context::create(vulkan));
  options.calibration = calibration.value_or(!context->caps().cpu);
  if (!calibration && context->caps().cpu) {
    options.calibration_off_reason = "no calibration on a CPU device (" +
                                     context->caps().device_name +
                                     "), where it takes minutes per scene: --calibration on";
    LOG_INFO << options.calibration_off_reason;
  }
  DDGI_ASSIGN_OR_RETURN(auto server, Server::start(*context, options));
  if (!port_file.empty()) write_port_file(port_file, server->port());
  std::printf("ddgi-server: listening on port %d\n", server->port());
  if (server->web_port() >= 0) {
    std::printf("ddgi-server: web client at http://localhost:%d/\n", server->web_port());
  }
  std::fflush(stdout);
  serve_until_stopped(*server, signals, options.shutdown_grace);
  server.reset();
  if (g_device_lost) {
    // Sessions have ended with the loss as their status; the supervisor restarts the server.
    return unavailable("the GPU device was lost; exiting so that the server is restarted");
  }
  Status validation = context->no_validation_messages();
  context.reset();
  return validation;
}

}  // namespace
}  // namespace ddgi::service

int main(int argc, char** argv) {
  // Before any thread starts (docs/service.md, "Memory"): sessions come and go on threads of
  // their own, and every arena they touch would keep what they freed.
  ddgi::service::limit_malloc_arenas(ddgi::service::kServerMallocArenas);
  const ddgi::Status status = ddgi::service::run(argc, argv);
  if (!status.ok()) {
    std::fprintf(stderr, "ddgi-server: %s\n", status.error().message.c_str());
    return status.error().code == ddgi::ErrorCode::kInvalidArgument ? 2 : 1;
  }
  return 0;
}
