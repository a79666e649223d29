// ddgi-client commands that fetch frames: one (RenderFrame) or a stream (StreamFrames, or the
// web front's WebSocket with --web), with optional camera moves that measure the latency from a
// command to the first frame showing it.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "encode/jpeg.h"
#include "encode/write_image.h"
#include "rpc/status_code_name.h"
#include "rpc/web_link.h"
#include "scene/camera_path.h"

namespace ddgi::client {
namespace {

using Clock = std::chrono::steady_clock;

Status write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary);
  file.write(bytes.data(), std::streamsize(bytes.size()));
  file.close();
  if (!file) return unavailable("cannot write " + path);
  return ok_status();
}

// JPEG files get the server's bytes untouched; other formats get the decoded pixels.
Status save_frame(const v1::Frame& frame, const std::string& path) {
  DDGI_ASSIGN_OR_RETURN(const encode::ImageFormat format, encode::format_from_path(path));
  if (format == encode::ImageFormat::kJpeg) return write_bytes(path, frame.jpeg());
  const auto* data = reinterpret_cast<const uint8_t*>(frame.jpeg().data());
  DDGI_ASSIGN_OR_RETURN(const encode::ImageRgba8 image,
                        encode::decode_jpeg({data, frame.jpeg().size()}));
  return encode::write_image(path, image);
}

// The frame's description without its pixels.
v1::Frame without_pixels(const v1::Frame& frame) {
  v1::Frame copy = frame;
  copy.clear_jpeg();
  return copy;
}

// Common to frame and stream: --view V, or settings and camera for a new view.
template <typename Request>
Status fill_view_request(const Flags& flags, Request& request) {
  DDGI_ASSIGN_OR_RETURN(*request.mutable_session_id(), session_flag(flags));
  DDGI_ASSIGN_OR_RETURN(*request.mutable_view_id(), flags.get_string("view", ""));
  DDGI_ASSIGN_OR_RETURN(*request.mutable_settings(), view_settings_flags(flags));
  DDGI_ASSIGN_OR_RETURN(const auto camera, camera_flags(flags));
  if (camera) *request.mutable_camera() = *camera;
  return ok_status();
}

int frame(Cli& cli) {
  v1::RenderFrameRequest request;
  if (Status status = fill_view_request(cli.flags, request); !status.ok()) {
    return report(status.error());
  }
  DDGI_CLI_TRY(const std::string out, cli.flags.get_string("out", ""));
  v1::Frame reply;
  auto context = cli.context();
  const grpc::Status status = cli.stub->RenderFrame(context.get(), request, &reply);
  if (!status.ok()) return report(status);
  if (!out.empty()) {
    if (Status saved = save_frame(reply, out); !saved.ok()) return report(saved.error());
  }
  print_json(without_pixels(reply));
  return 0;
}

// A camera turned about its vertical axis by `degrees`.
v1::Camera yawed(const v1::Camera& camera, double degrees) {
  const double a = degrees * 3.14159265358979 / 180.0;
  const v1::Vec3& f = camera.forward();
  v1::Camera out = camera;
  auto* forward = out.mutable_forward();
  forward->set_x(float(f.x() * std::cos(a) + f.z() * std::sin(a)));
  forward->set_y(f.y());
  forward->set_z(float(-f.x() * std::sin(a) + f.z() * std::cos(a)));
  return out;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, size_t(p * double(values.size() - 1) + 0.5))];
}

struct StreamOptions {
  int64_t max_frames = 0;
  double max_seconds = 0.0;  // 0: no time limit
  std::string out;           // the last frame
  std::string out_dir;       // every frame
  int64_t camera_moves = 0;
  std::optional<CameraPath> camera_path;  // --camera-path: moves follow it, else turn the camera
  double path_speed = 1.0;                // seconds of the path per second of the stream
  double move_interval = 0.0;
  int64_t stall_after = -1;  // stop reading after this frame for stall_seconds
  double stall_seconds = 0.0;
};

// The stream command's flags: the request, and the options of the reading side.
Result<StreamOptions> stream_options(const Flags& flags, v1::StreamFramesRequest& request) {
  DDGI_TRY(fill_view_request(flags, request));
  StreamOptions o;
  DDGI_ASSIGN_OR_RETURN(o.max_frames, flags.get_int("frames", 10, 1, 1ll << 40));
  DDGI_ASSIGN_OR_RETURN(o.max_seconds, flags.get_double("seconds", 0.0, 0.0, 1e7));
  DDGI_ASSIGN_OR_RETURN(const double max_fps, flags.get_double("max-fps", 0.0, 0.0, 1e6));
  request.set_max_fps(float(max_fps));
  DDGI_ASSIGN_OR_RETURN(o.out, flags.get_string("out", ""));
  DDGI_ASSIGN_OR_RETURN(o.out_dir, flags.get_string("out-dir", ""));
  DDGI_ASSIGN_OR_RETURN(o.camera_moves, flags.get_int("camera-moves", 0, 0, 100000));
  DDGI_ASSIGN_OR_RETURN(o.move_interval, flags.get_double("move-interval", 0.5, 0.001, 3600));
  DDGI_ASSIGN_OR_RETURN(const std::string path_file, flags.get_string("camera-path", ""));
  if (!path_file.empty()) {
    DDGI_ASSIGN_OR_RETURN(o.camera_path, read_camera_path(path_file));
    if (o.camera_moves == 0) return invalid_argument("--camera-path needs --camera-moves N");
  }
  DDGI_ASSIGN_OR_RETURN(o.path_speed, flags.get_double("path-speed", 1.0, 1e-3, 1e3));
  DDGI_ASSIGN_OR_RETURN(o.stall_after, flags.get_int("stall-after", -1, -1, 1ll << 40));
  DDGI_ASSIGN_OR_RETURN(o.stall_seconds, flags.get_double("stall-seconds", 0.0, 0.0, 3600));
  return o;
}

// The camera of move `i` (from 0) given the first frame's: turned back and forth by 2 degrees,
// or the camera path's pose at (i * interval * speed) seconds (the path's field of view kept
// from the first frame).
using MoveCamera = std::function<v1::Camera(int64_t i, const v1::Camera& first)>;

MoveCamera move_camera(const StreamOptions& o) {
  if (!o.camera_path) {
    return
        [](int64_t i, const v1::Camera& first) { return yawed(first, (i % 2 == 0) ? 2.0 : 0.0); };
  }
  return [path = *o.camera_path, step = o.move_interval * o.path_speed](int64_t i,
                                                                        const v1::Camera& first) {
    const CameraPose pose = path.pose_at(double(i) * step);
    v1::Camera camera;
    camera.set_vertical_fov_degrees(first.vertical_fov_degrees());
    auto set = [](v1::Vec3* v, glm::vec3 p) {
      v->set_x(p.x);
      v->set_y(p.y);
      v->set_z(p.z);
    };
    set(camera.mutable_position(), pose.position);
    set(camera.mutable_target(), pose.target);
    return camera;
  };
}

// --camera-moves: SetCamera calls on a thread beside the stream reader, moving the camera of
// the first frame (move_camera). Each move remembers when it was sent, so the reader can time
// the first frame that shows it.
class CameraMover {
 public:
  using SetCamera = std::function<grpc::Status(const v1::SetCameraRequest&, v1::ViewInfo*)>;
  CameraMover(SetCamera set_camera, MoveCamera next, int64_t moves, double interval)
      : set_camera_(std::move(set_camera)), next_(std::move(next)) {
    if (moves > 0) thread_ = std::thread([this, moves, interval] { run(moves, interval); });
  }
  ~CameraMover() { finish(); }
  CameraMover(const CameraMover&) = delete;
  CameraMover& operator=(const CameraMover&) = delete;

  // The reader got `frame` at `now`: the first frame starts the moves; adds the latency (ms)
  // of every move this frame is the first to show to `latencies`.
  void on_frame(const v1::Frame& frame, Clock::time_point now, std::vector<double>& latencies) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!first_) {
      first_ = frame;
      first_frame_.notify_all();
    }
    for (Probe& probe : probes_) {
      if (!probe.seen && probe.seq <= frame.last_command_seq()) {
        probe.seen = true;
        latencies.push_back(std::chrono::duration<double, std::milli>(now - probe.sent).count());
      }
    }
  }

  // Stops the moves and waits for the thread; the error of the move that failed, if one did.
  std::string finish() {
    done_ = true;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      first_frame_.notify_all();
    }
    if (thread_.joinable()) thread_.join();
    return error_;
  }

 private:
  struct Probe {
    uint64_t seq = 0;
    Clock::time_point sent;
    bool seen = false;
  };

  void run(int64_t moves, double interval) {
    v1::Frame initial;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      first_frame_.wait(lock, [&] { return first_.has_value() || done_.load(); });
      if (!first_) return;
      initial = *first_;
    }
    for (int64_t i = 0; i < moves && !done_; ++i) {
      std::this_thread::sleep_for(std::chrono::duration<double>(interval));
      v1::SetCameraRequest move;
      move.set_session_id(initial.session_id());
      move.set_view_id(initial.view_id());
      *move.mutable_camera() = next_(i, initial.camera());
      v1::ViewInfo reply;
      const auto sent = Clock::now();
      const grpc::Status status = set_camera_(move, &reply);
      std::lock_guard<std::mutex> lock(mutex_);
      if (!status.ok()) {
        error_ = status.error_message();
        return;
      }
      probes_.push_back({reply.command_seq(), sent, false});
    }
  }

  SetCamera set_camera_;
  MoveCamera next_;
  std::mutex mutex_;
  std::condition_variable first_frame_;
  std::optional<v1::Frame> first_;
  std::vector<Probe> probes_;
  std::atomic<bool> done_{false};
  std::string error_;
  std::thread thread_;
};

// What the reader saw.
struct StreamTotals {
  int64_t count = 0;
  double gpu_ms = 0.0;
  double gi_update_ms = 0.0;
  double encode_ms = 0.0;
  double bytes = 0.0;
  std::vector<double> latencies;  // ms, of the camera moves measured
  v1::Frame last;
  bool server_ended = false;
};

// Where a stream's frames come from and its camera moves go: the gRPC stream, or the web
// front's WebSocket (--web PORT), so that the two are measured the same way.
struct StreamLink {
  std::function<bool(v1::Frame*)> next;  // false: the server ended the stream
  CameraMover::SetCamera set_camera;
  // Ends the stream (when the server has not) and says how it ended.
  std::function<grpc::Status(bool server_ended)> finish;
};

StreamLink grpc_link(Cli& cli, const v1::StreamFramesRequest& request) {
  std::shared_ptr<grpc::ClientContext> context = cli.context(false);  // lives until we are done
  std::shared_ptr<grpc::ClientReader<v1::Frame>> reader =
      cli.stub->StreamFrames(context.get(), request);
  StreamLink link;
  link.next = [reader](v1::Frame* frame) { return reader->Read(frame); };
  link.set_camera = [&cli](const v1::SetCameraRequest& move, v1::ViewInfo* reply) {
    auto unary = cli.context();
    return cli.stub->SetCamera(unary.get(), move, reply);
  };
  link.finish = [context, reader](bool server_ended) {
    // A client ends a stream by cancelling it; the server ends it with a status.
    if (!server_ended) context->TryCancel();
    const grpc::Status status = reader->Finish();
    return server_ended ? status : grpc::Status::OK;
  };
  return link;
}

grpc::Status web_status(const v1::WebReply& reply) {
  if (!reply.has_error()) return grpc::Status::OK;
  return grpc::Status(status_code_from_name(reply.error().code()), reply.error().message());
}

// The same stream through the web front at HOST:port (HOST from --server), as a browser gets it.
Result<StreamLink> web_link(Cli& cli, const v1::StreamFramesRequest& request, int port) {
  const std::string& server = cli.connection.server;
  const std::string host = server.substr(0, server.rfind(':'));
  DDGI_ASSIGN_OR_RETURN(std::shared_ptr<WebLink> web, WebLink::connect(host, port));
  v1::WebRequest hello;
  hello.mutable_hello()->set_token(cli.connection.token);
  if (grpc::Status said = web_status(web->call(hello)); !said.ok()) {
    return unavailable("the web front refused hello: " + said.error_message());
  }
  v1::WebRequest stream;
  *stream.mutable_stream_frames() = request;
  const v1::WebReply started = web->call(stream);
  if (!started.has_stream_started()) return unavailable(web_status(started).error_message());
  const uint64_t stream_id = started.id();
  auto ended = std::make_shared<v1::WebReply>();
  StreamLink link;
  link.next = [web, stream_id, ended](v1::Frame* frame) {
    while (!web->next_frame(frame, 0.1)) {
      if (web->wait_reply(stream_id, ended.get(), 0.0) || web->closed()) return false;
    }
    return true;
  };
  link.set_camera = [web](const v1::SetCameraRequest& move, v1::ViewInfo* reply) {
    v1::WebRequest call;
    *call.mutable_set_camera() = move;
    const v1::WebReply answer = web->call(call);
    *reply = answer.view();
    return web_status(answer);
  };
  link.finish = [web, ended](bool server_ended) {
    if (!server_ended) return grpc::Status::OK;  // closing the link ends the stream
    if (!ended->has_stream_ended()) return grpc::Status(grpc::StatusCode::UNAVAILABLE, "closed");
    const v1::WebStreamEnded& how = ended->stream_ended();
    return grpc::Status(status_code_from_name(how.code()), how.message());
  };
  return link;
}

// Reads frames until --frames or --seconds, or until the server ends the stream.
Status read_stream(StreamLink& link, const StreamOptions& o, Clock::time_point start,
                   CameraMover& mover, StreamTotals& totals) {
  v1::Frame frame;
  while (totals.count < o.max_frames) {
    if (!link.next(&frame)) {
      totals.server_ended = true;
      break;
    }
    const auto now = Clock::now();
    ++totals.count;
    totals.gpu_ms += frame.gpu_ms();
    totals.gi_update_ms += frame.gi_update_ms();
    totals.encode_ms += frame.encode_ms();
    totals.bytes += double(frame.jpeg().size());
    mover.on_frame(frame, now, totals.latencies);
    if (!o.out_dir.empty()) {
      char name[64];
      std::snprintf(name, sizeof(name), "/frame_%06lld.jpg", static_cast<long long>(totals.count));
      DDGI_TRY(write_bytes(o.out_dir + name, frame.jpeg()));
    }
    totals.last = std::move(frame);
    if (totals.count == o.stall_after) {
      // Stop reading for a while, as a slow client would: the server must drop, not buffer.
      std::this_thread::sleep_for(std::chrono::duration<double>(o.stall_seconds));
    }
    if (o.max_seconds > 0.0 &&
        std::chrono::duration<double>(now - start).count() >= o.max_seconds) {
      break;
    }
  }
  return ok_status();
}

nlohmann::json stream_summary(const StreamTotals& t, double seconds, int64_t camera_moves) {
  const double count = double(t.count);
  nlohmann::json summary;
  summary["frames"] = t.count;
  summary["seconds"] = seconds;
  summary["fps"] = seconds > 0 ? count / seconds : 0.0;
  summary["ended_by"] = t.server_ended ? "server" : "client";
  summary["view_id"] = t.last.view_id();
  summary["width"] = t.last.width();
  summary["height"] = t.last.height();
  summary["frames_dropped"] = t.last.frames_dropped();
  summary["last_frame_index"] = t.last.frame_index();
  const v1::Vec3& at = t.last.camera().position();
  summary["last_camera_position"] = {at.x(), at.y(), at.z()};
  summary["gpu_ms_mean"] = t.count ? t.gpu_ms / count : 0.0;
  summary["gi_update_ms_mean"] = t.count ? t.gi_update_ms / count : 0.0;
  summary["encode_ms_mean"] = t.count ? t.encode_ms / count : 0.0;
  summary["jpeg_bytes_mean"] = t.count ? t.bytes / count : 0.0;
  if (camera_moves > 0) {
    double sum = 0.0;
    for (double l : t.latencies) sum += l;
    const double mean = t.latencies.empty() ? 0.0 : sum / double(t.latencies.size());
    summary["latency_ms"] = {{"moves", camera_moves},
                             {"measured", t.latencies.size()},
                             {"mean", mean},
                             {"p50", percentile(t.latencies, 0.5)},
                             {"p90", percentile(t.latencies, 0.9)},
                             {"max", percentile(t.latencies, 1.0)}};
  }
  return summary;
}

int stream(Cli& cli) {
  v1::StreamFramesRequest request;
  DDGI_CLI_TRY(const StreamOptions options, stream_options(cli.flags, request));
  DDGI_CLI_TRY(const int64_t web_port, cli.flags.get_int("web", 0, 0, 65535));
  StreamLink link;
  if (web_port > 0) {
    DDGI_CLI_TRY(link, web_link(cli, request, int(web_port)));
  } else {
    link = grpc_link(cli, request);
  }
  const auto start = Clock::now();
  CameraMover mover(link.set_camera, move_camera(options), options.camera_moves,
                    options.move_interval);
  StreamTotals totals;
  if (Status read = read_stream(link, options, start, mover, totals); !read.ok()) {
    return report(read.error());
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const std::string move_error = mover.finish();
  if (const grpc::Status status = link.finish(totals.server_ended); !status.ok()) {
    return report(status);
  }
  if (!move_error.empty()) {
    return report(grpc::Status(grpc::StatusCode::UNKNOWN, "camera move: " + move_error));
  }
  if (!options.out.empty() && totals.count > 0) {
    if (Status saved = save_frame(totals.last, options.out); !saved.ok()) {
      return report(saved.error());
    }
  }
  std::printf("%s\n", stream_summary(totals, seconds, options.camera_moves).dump(2).c_str());
  return 0;
}

}  // namespace

void add_frame_commands(std::vector<CommandSpec>& commands) {
  std::vector<std::string> frame_flags = view_setting_flag_names();
  for (const char* name : {"session", "view", "out"}) frame_flags.push_back(name);
  commands.push_back({"frame",
                      "--session ID (--view V | [--width N --height N --camera "
                      "px,py,pz,tx,ty,tz[,fov] ...]) [--out FILE.jpg|.png]",
                      "render one frame; prints its description, writes the image",
                      frame_flags,
                      {},
                      frame});
  std::vector<std::string> stream_flags = frame_flags;
  for (const char* name :
       {"frames", "seconds", "max-fps", "out-dir", "camera-moves", "move-interval", "camera-path",
        "path-speed", "stall-after", "stall-seconds", "web"}) {
    stream_flags.push_back(name);
  }
  commands.push_back(
      {"stream",
       "--session ID (--view V | settings as frame) [--frames N] [--seconds S] "
       "[--max-fps X] [--out LAST.jpg] [--out-dir DIR] [--camera-moves N "
       "--move-interval S [--camera-path FILE.path.json --path-speed X]] [--stall-after N "
       "--stall-seconds S] [--web PORT]",
       "stream frames; prints fps, drops, GPU/field/encode times and, with "
       "--camera-moves, the latency from a camera command to the first frame "
       "showing it (the moves turn the camera by 2 degrees back and forth, or "
       "follow --camera-path from its start, X path seconds per second); --web: "
       "through the server's web front on PORT (the WebSocket a browser uses) "
       "instead of gRPC",
       stream_flags,
       {},
       stream});
}

}  // namespace ddgi::client
