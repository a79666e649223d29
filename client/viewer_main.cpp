// ddgi-viewer: a window on a ddgi-server stream. Keyboard and mouse move the camera (sent as
// SetCamera RPCs); a stats line shows frames per second, the latency from a camera move to the
// first frame that shows it, and the server's GPU and encode times.
//
//   W/S forward/back, A/D left/right, Q/E down/up, arrows or left-drag to look, R: the first
//   camera again, Escape: quit.
#include <SDL.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "connection.h"
#include "core/flags.h"
#include "encode/write_image.h"
#include "viewer_font.h"
#include "viewer_link.h"

namespace ddgi::client {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-viewer [flags]

Shows the frames of a ddgi-server session in a window and turns keyboard and mouse into
camera moves. Without --session it creates a session on --scene and closes it on exit.

  --session ID          an existing session
  --scene NAME          scene for a new session                        [cornell_box]
  --width N --height N  frame size                                     [640 x 480]
  --max-fps X           frames per second at most (0: as made)         [30]
  --quality Q           JPEG quality 1..100 (lower for slow links)      [80]
  --frames N            exit after showing N frames (0: run until closed) [0]
  --screenshot FILE     on exit, write what the window shows (.png/.jpg)
  --speed X             metres per second of the movement keys          [1]
)";

using Clock = std::chrono::steady_clock;

struct CameraState {
  v1::Vec3 position;
  double yaw = 0.0, pitch = 0.0;  // radians; yaw 0 looks down -Z
  float fov = 45.0f;

  static CameraState from(const v1::Camera& camera) {
    CameraState state;
    state.position = camera.position();
    const v1::Vec3& f = camera.forward();
    state.yaw = std::atan2(double(f.x()), -double(f.z()));
    state.pitch = std::asin(std::clamp(double(f.y()), -1.0, 1.0));
    state.fov = camera.vertical_fov_degrees();
    return state;
  }
  void forward_vector(double& x, double& y, double& z) const {
    x = std::sin(yaw) * std::cos(pitch);
    y = std::sin(pitch);
    z = -std::cos(yaw) * std::cos(pitch);
  }
  v1::Camera to_camera() const {
    v1::Camera camera;
    *camera.mutable_position() = position;
    double x, y, z;
    forward_vector(x, y, z);
    camera.mutable_forward()->set_x(float(x));
    camera.mutable_forward()->set_y(float(y));
    camera.mutable_forward()->set_z(float(z));
    camera.mutable_up()->set_y(1.0f);
    camera.set_vertical_fov_degrees(fov);
    return camera;
  }
  void move(double forward, double right, double up) {
    double fx, fy, fz;
    forward_vector(fx, fy, fz);
    const double rx = std::cos(yaw), rz = std::sin(yaw);
    position.set_x(float(position.x() + forward * fx + right * rx));
    position.set_y(float(position.y() + forward * fy + up));
    position.set_z(float(position.z() + forward * fz + right * rz));
  }
};

// Session lifetime when the viewer made it.
class OwnedSession {
 public:
  OwnedSession(const ConnectionOptions& connection, std::string id)
      : connection_(connection), id_(std::move(id)) {}
  ~OwnedSession() {
    if (id_.empty()) return;
    auto stub = v1::RenderService::NewStub(make_channel(connection_));
    grpc::ClientContext context;
    prepare(context, connection_);
    v1::CloseSessionRequest request;
    request.set_session_id(id_);
    v1::CloseSessionReply reply;
    (void)stub->CloseSession(&context, request, &reply);
  }

 private:
  ConnectionOptions connection_;
  std::string id_;
};

std::string stats_line(double fps, const LinkStats& link, const v1::Frame& frame) {
  char text[160];
  std::snprintf(
      text, sizeof(text), "FPS %.1f  LAT %s  GPU %.1f MS  ENC %.1f MS  DROP %llu  %uX%u", fps,
      link.latency_ms > 0 ? (std::to_string(int(link.latency_ms + 0.5)) + " MS").c_str() : "-",
      frame.gpu_ms(), frame.encode_ms(), static_cast<unsigned long long>(frame.frames_dropped()),
      frame.width(), frame.height());
  return text;
}

Status save_screenshot(SDL_Renderer* renderer, const encode::ImageRgba8& fallback,
                       const std::string& path) {
  int width = 0, height = 0;
  encode::ImageRgba8 shot;
  if (SDL_GetRendererOutputSize(renderer, &width, &height) == 0 && width > 0 && height > 0) {
    shot = {uint32_t(width), uint32_t(height), std::vector<uint8_t>(size_t(width) * height * 4)};
    if (SDL_RenderReadPixels(renderer, nullptr, SDL_PIXELFORMAT_ABGR8888, shot.pixels.data(),
                             width * 4) != 0) {
      shot = fallback;  // some drivers cannot read back; the last frame shown is the same image
    }
  } else {
    shot = fallback;
  }
  return encode::write_image(path, shot);
}

Status run(int argc, char** argv) {
  std::vector<std::string> known = connection_flags();
  for (const char* name : {"session", "scene", "width", "height", "max-fps", "quality", "frames",
                           "screenshot", "speed"}) {
    known.push_back(name);
  }
  DDGI_ASSIGN_OR_RETURN(Flags flags, Flags::parse(argc, argv, known, {"tls", "help"}));
  if (flags.has("help")) {
    std::printf("%s\n%s", kUsage, connection_usage());
    return ok_status();
  }
  DDGI_ASSIGN_OR_RETURN(const ConnectionOptions connection, connection_options(flags));
  DDGI_ASSIGN_OR_RETURN(std::string session, flags.get_string("session", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string scene, flags.get_string("scene", "cornell_box"));
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 640, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 480, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const double max_fps, flags.get_double("max-fps", 30, 0, 1000));
  DDGI_ASSIGN_OR_RETURN(const int64_t quality, flags.get_int("quality", 80, 1, 100));
  DDGI_ASSIGN_OR_RETURN(const int64_t max_frames, flags.get_int("frames", 0, 0, 1ll << 40));
  DDGI_ASSIGN_OR_RETURN(const std::string screenshot, flags.get_string("screenshot", ""));
  DDGI_ASSIGN_OR_RETURN(const double speed, flags.get_double("speed", 1.0, 1e-6, 1e6));
  if (!screenshot.empty()) DDGI_TRY(encode::format_from_path(screenshot));

  std::unique_ptr<OwnedSession> owned;
  if (session.empty()) {
    auto stub = v1::RenderService::NewStub(make_channel(connection));
    grpc::ClientContext context;
    prepare(context, connection);
    v1::CreateSessionRequest request;
    request.mutable_scene()->set_name(scene);
    v1::SessionInfo info;
    const grpc::Status status = stub->CreateSession(&context, request, &info);
    if (!status.ok()) {
      return unavailable(std::string("CreateSession: ") + status_code_name(status.error_code()) +
                         ": " + status.error_message());
    }
    session = info.session_id();
    owned = std::make_unique<OwnedSession>(connection, session);
  }

  if (SDL_Init(SDL_INIT_VIDEO) != 0) {
    return unavailable(std::string("SDL_Init: ") + SDL_GetError());
  }
  SDL_Window* window =
      SDL_CreateWindow("ddgi-viewer", SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, int(width),
                       int(height), SDL_WINDOW_RESIZABLE);
  if (!window) return unavailable(std::string("SDL_CreateWindow: ") + SDL_GetError());
  SDL_Renderer* renderer = SDL_CreateRenderer(window, -1, 0);
  if (!renderer) renderer = SDL_CreateRenderer(window, -1, SDL_RENDERER_SOFTWARE);
  if (!renderer) return unavailable(std::string("SDL_CreateRenderer: ") + SDL_GetError());
  SDL_Texture* texture = nullptr;

  v1::StreamFramesRequest request;
  request.set_session_id(session);
  request.mutable_settings()->set_width(uint32_t(width));
  request.mutable_settings()->set_height(uint32_t(height));
  request.mutable_settings()->set_jpeg_quality(uint32_t(quality));
  request.set_max_fps(float(max_fps));
  Status result = ok_status();
  {
    ViewerLink link(connection, request);
    std::optional<CameraState> camera, first_camera;
    encode::ImageRgba8 shown;
    int64_t frames_shown = 0;
    double fps = 0.0;
    auto fps_start = Clock::now();
    int fps_frames = 0;
    auto last_tick = Clock::now();
    bool running = true, dragging = false;
    while (running) {
      SDL_Event event;
      bool camera_changed = false;
      while (SDL_WaitEventTimeout(&event, 5)) {
        if (event.type == SDL_QUIT) running = false;
        if (event.type == SDL_KEYDOWN && event.key.keysym.sym == SDLK_ESCAPE) running = false;
        if (event.type == SDL_KEYDOWN && event.key.keysym.sym == SDLK_r && first_camera) {
          camera = first_camera;
          camera_changed = true;
        }
        if (event.type == SDL_MOUSEBUTTONDOWN && event.button.button == SDL_BUTTON_LEFT) {
          dragging = true;
        }
        if (event.type == SDL_MOUSEBUTTONUP && event.button.button == SDL_BUTTON_LEFT) {
          dragging = false;
        }
        if (event.type == SDL_MOUSEMOTION && dragging && camera) {
          camera->yaw += event.motion.xrel * 0.005;
          camera->pitch = std::clamp(camera->pitch - event.motion.yrel * 0.005, -1.5, 1.5);
          camera_changed = true;
        }
        if (!running) break;
      }
      // Held keys move continuously, scaled by the time since the last tick.
      const auto now = Clock::now();
      const double dt = std::min(0.1, std::chrono::duration<double>(now - last_tick).count());
      last_tick = now;
      const Uint8* keys = SDL_GetKeyboardState(nullptr);
      if (camera) {
        const double step = speed * dt, turn = 1.5 * dt;
        const double forward = (keys[SDL_SCANCODE_W] - keys[SDL_SCANCODE_S]) * step;
        const double right = (keys[SDL_SCANCODE_D] - keys[SDL_SCANCODE_A]) * step;
        const double up = (keys[SDL_SCANCODE_E] - keys[SDL_SCANCODE_Q]) * step;
        const double yaw = (keys[SDL_SCANCODE_RIGHT] - keys[SDL_SCANCODE_LEFT]) * turn;
        const double pitch = (keys[SDL_SCANCODE_UP] - keys[SDL_SCANCODE_DOWN]) * turn;
        if (forward != 0 || right != 0 || up != 0 || yaw != 0 || pitch != 0) {
          camera->move(forward, right, up);
          camera->yaw += yaw;
          camera->pitch = std::clamp(camera->pitch + pitch, -1.5, 1.5);
          camera_changed = true;
        }
      }
      if (camera_changed && camera) link.move_camera(camera->to_camera());

      if (auto frame = link.take_frame()) {
        if (!camera) {
          camera = CameraState::from(frame->info.camera());
          first_camera = camera;
        }
        ++fps_frames;
        const double elapsed = std::chrono::duration<double>(now - fps_start).count();
        if (elapsed >= 0.5) {
          fps = fps_frames / elapsed;
          fps_frames = 0;
          fps_start = now;
        }
        shown = std::move(frame->image);
        const int scale = shown.width >= 480 ? 2 : 1;
        draw_text(shown, 4 * scale, 4 * scale, stats_line(fps, link.stats(), frame->info), scale);
        if (texture) {
          int tw = 0, th = 0;
          SDL_QueryTexture(texture, nullptr, nullptr, &tw, &th);
          if (uint32_t(tw) != shown.width || uint32_t(th) != shown.height) {
            SDL_DestroyTexture(texture);
            texture = nullptr;
          }
        }
        if (!texture) {
          texture =
              SDL_CreateTexture(renderer, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STREAMING,
                                int(shown.width), int(shown.height));
        }
        SDL_UpdateTexture(texture, nullptr, shown.pixels.data(), int(shown.width) * 4);
        SDL_RenderClear(renderer);
        SDL_RenderCopy(renderer, texture, nullptr, nullptr);
        if (!screenshot.empty() && max_frames > 0 && frames_shown + 1 == max_frames) {
          // Read back before presenting: the back buffer is defined only until then.
          result = save_screenshot(renderer, shown, screenshot);
        }
        SDL_RenderPresent(renderer);
        ++frames_shown;
        if (max_frames > 0 && frames_shown >= max_frames) running = false;
      }
      if (link.ended()) {
        const grpc::Status status = link.status();
        if (!status.ok()) {
          result = unavailable(std::string("stream: ") + status_code_name(status.error_code()) +
                               ": " + status.error_message());
        }
        running = false;
      }
    }
    if (!screenshot.empty() && (max_frames == 0 || frames_shown < max_frames) && result.ok() &&
        !shown.pixels.empty()) {
      result = encode::write_image(screenshot, shown);
    }
    std::printf("{\"frames_shown\": %lld, \"fps\": %.2f, \"latency_ms\": %.1f}\n",
                static_cast<long long>(frames_shown), fps, link.stats().latency_ms);
  }
  if (texture) SDL_DestroyTexture(texture);
  SDL_DestroyRenderer(renderer);
  SDL_DestroyWindow(window);
  SDL_Quit();
  return result;
}

}  // namespace
}  // namespace ddgi::client

int main(int argc, char** argv) {
  const ddgi::Status status = ddgi::client::run(argc, argv);
  if (!status.ok()) {
    std::fprintf(stderr, "ddgi-viewer: %s\n", status.error().message.c_str());
    return status.error().code == ddgi::ErrorCode::kInvalidArgument ? 2 : 1;
  }
  return 0;
}
