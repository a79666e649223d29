// ddgi-client commands that fetch frames: one (RenderFrame) or a stream (StreamFrames), with
// optional camera moves that measure the latency from a command to the first frame showing it.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "encode/jpeg.h"
#include "encode/write_image.h"

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

struct LatencyProbe {
  uint64_t seq = 0;
  Clock::time_point sent;
  bool seen = false;
};

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, size_t(p * double(values.size() - 1) + 0.5))];
}

int stream(Cli& cli) {
  v1::StreamFramesRequest request;
  if (Status status = fill_view_request(cli.flags, request); !status.ok()) {
    return report(status.error());
  }
  DDGI_CLI_TRY(const int64_t max_frames, cli.flags.get_int("frames", 10, 1, 1ll << 40));
  DDGI_CLI_TRY(const double max_seconds, cli.flags.get_double("seconds", 0.0, 0.0, 1e7));
  DDGI_CLI_TRY(const double max_fps, cli.flags.get_double("max-fps", 0.0, 0.0, 1e6));
  request.set_max_fps(float(max_fps));
  DDGI_CLI_TRY(const std::string out, cli.flags.get_string("out", ""));
  DDGI_CLI_TRY(const std::string out_dir, cli.flags.get_string("out-dir", ""));
  DDGI_CLI_TRY(const int64_t camera_moves, cli.flags.get_int("camera-moves", 0, 0, 100000));
  DDGI_CLI_TRY(const double move_interval, cli.flags.get_double("move-interval", 0.5, 0.001, 3600));
  DDGI_CLI_TRY(const int64_t stall_after, cli.flags.get_int("stall-after", -1, -1, 1ll << 40));
  DDGI_CLI_TRY(const double stall_seconds, cli.flags.get_double("stall-seconds", 0.0, 0.0, 3600));

  auto context = cli.context(false);  // a stream lives until we have what we want
  auto reader = cli.stub->StreamFrames(context.get(), request);
  const auto start = Clock::now();

  // Camera moves run beside the reader: they need the view id and camera of the first frame.
  std::mutex mutex;
  std::condition_variable first_frame;
  std::optional<v1::Frame> first;
  std::vector<LatencyProbe> probes;
  std::atomic<bool> done{false};
  std::string move_error;
  std::thread mover;
  if (camera_moves > 0) {
    mover = std::thread([&] {
      v1::Frame initial;
      {
        std::unique_lock<std::mutex> lock(mutex);
        first_frame.wait(lock, [&] { return first.has_value() || done.load(); });
        if (!first) return;
        initial = *first;
      }
      for (int64_t i = 0; i < camera_moves && !done; ++i) {
        std::this_thread::sleep_for(std::chrono::duration<double>(move_interval));
        v1::SetCameraRequest move;
        move.set_session_id(initial.session_id());
        move.set_view_id(initial.view_id());
        *move.mutable_camera() = yawed(initial.camera(), (i % 2 == 0) ? 2.0 : 0.0);
        v1::ViewInfo reply;
        auto move_context = cli.context();
        const auto sent = Clock::now();
        const grpc::Status status = cli.stub->SetCamera(move_context.get(), move, &reply);
        std::lock_guard<std::mutex> lock(mutex);
        if (!status.ok()) {
          move_error = status.error_message();
          return;
        }
        probes.push_back({reply.command_seq(), sent, false});
      }
    });
  }

  v1::Frame frame, last;
  int64_t count = 0;
  double gpu_ms = 0.0, encode_ms = 0.0, bytes = 0.0;
  std::vector<double> latencies;
  bool server_ended = false;
  while (count < max_frames) {
    if (!reader->Read(&frame)) {
      server_ended = true;
      break;
    }
    const auto now = Clock::now();
    ++count;
    gpu_ms += frame.gpu_ms();
    encode_ms += frame.encode_ms();
    bytes += double(frame.jpeg().size());
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (!first) {
        first = frame;
        first_frame.notify_all();
      }
      for (LatencyProbe& probe : probes) {
        if (!probe.seen && probe.seq <= frame.last_command_seq()) {
          probe.seen = true;
          latencies.push_back(std::chrono::duration<double, std::milli>(now - probe.sent).count());
        }
      }
    }
    if (!out_dir.empty()) {
      char name[64];
      std::snprintf(name, sizeof(name), "/frame_%06lld.jpg", static_cast<long long>(count));
      if (Status saved = write_bytes(out_dir + name, frame.jpeg()); !saved.ok()) {
        return report(saved.error());
      }
    }
    last = std::move(frame);
    if (count == stall_after) {
      // Stop reading for a while, as a slow client would: the server must drop, not buffer.
      std::this_thread::sleep_for(std::chrono::duration<double>(stall_seconds));
    }
    if (max_seconds > 0.0 && std::chrono::duration<double>(now - start).count() >= max_seconds) {
      break;
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  done = true;
  {
    std::lock_guard<std::mutex> lock(mutex);
    first_frame.notify_all();
  }
  if (mover.joinable()) mover.join();
  // A client ends a stream by cancelling it; the server ends it with a status.
  if (!server_ended) context->TryCancel();
  const grpc::Status status = reader->Finish();
  const bool cancelled_by_us = !server_ended;
  if (server_ended && !status.ok()) return report(status);
  if (!move_error.empty()) {
    return report(grpc::Status(grpc::StatusCode::UNKNOWN, "camera move: " + move_error));
  }
  if (!out.empty() && count > 0) {
    if (Status saved = save_frame(last, out); !saved.ok()) return report(saved.error());
  }

  nlohmann::json summary;
  summary["frames"] = count;
  summary["seconds"] = seconds;
  summary["fps"] = seconds > 0 ? double(count) / seconds : 0.0;
  summary["ended_by"] = cancelled_by_us ? "client" : "server";
  summary["view_id"] = last.view_id();
  summary["width"] = last.width();
  summary["height"] = last.height();
  summary["frames_dropped"] = last.frames_dropped();
  summary["last_frame_index"] = last.frame_index();
  summary["gpu_ms_mean"] = count ? gpu_ms / double(count) : 0.0;
  summary["encode_ms_mean"] = count ? encode_ms / double(count) : 0.0;
  summary["jpeg_bytes_mean"] = count ? bytes / double(count) : 0.0;
  if (camera_moves > 0) {
    double sum = 0.0;
    for (double l : latencies) sum += l;
    summary["latency_ms"] = {{"moves", camera_moves},
                             {"measured", latencies.size()},
                             {"mean", latencies.empty() ? 0.0 : sum / double(latencies.size())},
                             {"p50", percentile(latencies, 0.5)},
                             {"p90", percentile(latencies, 0.9)},
                             {"max", percentile(latencies, 1.0)}};
  }
  std::printf("%s\n", summary.dump(2).c_str());
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
  for (const char* name : {"frames", "seconds", "max-fps", "out-dir", "camera-moves",
                           "move-interval", "stall-after", "stall-seconds"}) {
    stream_flags.push_back(name);
  }
  commands.push_back({"stream",
                      "--session ID (--view V | settings as frame) [--frames N] [--seconds S] "
                      "[--max-fps X] [--out LAST.jpg] [--out-dir DIR] [--camera-moves N "
                      "--move-interval S] [--stall-after N --stall-seconds S]",
                      "stream frames; prints fps, drops, GPU/encode times and, with "
                      "--camera-moves, the latency from a camera command to the first frame "
                      "showing it",
                      stream_flags,
                      {},
                      stream});
}

}  // namespace ddgi::client
