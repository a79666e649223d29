// ddgi-viewer: a window on a ddgi-server stream. Keyboard and mouse move the camera (sent as
// SetCamera RPCs); a stats line shows frames per second, the latency from a camera move to the
// first frame that shows it, and the server's GPU and encode times.
//
//   W/S forward/back, A/D left/right, Q/E down/up, arrows or left-drag to look, R: the first
//   camera again, Escape: quit.
#include <SDL.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
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

struct ViewerOptions {
  ConnectionOptions connection;
  std::string session;  // empty: create one on `scene`
  std::string scene;
  int64_t width = 0;
  int64_t height = 0;
  double max_fps = 0.0;
  int64_t quality = 0;
  int64_t max_frames = 0;  // 0: until the window closes
  std::string screenshot;
  double speed = 0.0;
};

// The flags as options; nullopt after --help (the usage is printed).
Result<std::optional<ViewerOptions>> parse_options(int argc, char** argv) {
  std::vector<std::string> known = connection_flags();
  for (const char* name : {"session", "scene", "width", "height", "max-fps", "quality", "frames",
                           "screenshot", "speed"}) {
    known.push_back(name);
  }
  DDGI_ASSIGN_OR_RETURN(Flags flags, Flags::parse(argc, argv, known, {"tls", "help"}));
  if (flags.has("help")) {
    std::printf("%s\n%s", kUsage, connection_usage());
    return std::optional<ViewerOptions>();
  }
  ViewerOptions o;
  DDGI_ASSIGN_OR_RETURN(o.connection, connection_options(flags));
  DDGI_ASSIGN_OR_RETURN(o.session, flags.get_string("session", ""));
  DDGI_ASSIGN_OR_RETURN(o.scene, flags.get_string("scene", "cornell_box"));
  DDGI_ASSIGN_OR_RETURN(o.width, flags.get_int("width", 640, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(o.height, flags.get_int("height", 480, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(o.max_fps, flags.get_double("max-fps", 30, 0, 1000));
  DDGI_ASSIGN_OR_RETURN(o.quality, flags.get_int("quality", 80, 1, 100));
  DDGI_ASSIGN_OR_RETURN(o.max_frames, flags.get_int("frames", 0, 0, 1ll << 40));
  DDGI_ASSIGN_OR_RETURN(o.screenshot, flags.get_string("screenshot", ""));
  DDGI_ASSIGN_OR_RETURN(o.speed, flags.get_double("speed", 1.0, 1e-6, 1e6));
  if (!o.screenshot.empty()) DDGI_TRY(encode::format_from_path(o.screenshot));
  return std::optional<ViewerOptions>(std::move(o));
}

// A new session on `scene`; its id.
Result<std::string> create_session(const ConnectionOptions& connection, const std::string& scene) {
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
  return info.session_id();
}

// The SDL window, its renderer and the texture frames are drawn through.
class ViewerWindow {
 public:
  ViewerWindow() = default;
  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;
  ~ViewerWindow() {
    if (texture_) SDL_DestroyTexture(texture_);
    if (renderer_) SDL_DestroyRenderer(renderer_);
    if (window_) SDL_DestroyWindow(window_);
    if (sdl_) SDL_Quit();
  }

  Status open(int width, int height) {
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
      return unavailable(std::string("SDL_Init: ") + SDL_GetError());
    }
    sdl_ = true;
    window_ = SDL_CreateWindow("ddgi-viewer", SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED,
                               width, height, SDL_WINDOW_RESIZABLE);
    if (!window_) return unavailable(std::string("SDL_CreateWindow: ") + SDL_GetError());
    renderer_ = SDL_CreateRenderer(window_, -1, 0);
    if (!renderer_) renderer_ = SDL_CreateRenderer(window_, -1, SDL_RENDERER_SOFTWARE);
    if (!renderer_) return unavailable(std::string("SDL_CreateRenderer: ") + SDL_GetError());
    return ok_status();
  }

  // Draws `image` over the whole window, not yet presented.
  void draw(const encode::ImageRgba8& image) {
    if (texture_) {
      int tw = 0, th = 0;
      SDL_QueryTexture(texture_, nullptr, nullptr, &tw, &th);
      if (uint32_t(tw) != image.width || uint32_t(th) != image.height) {
        SDL_DestroyTexture(texture_);
        texture_ = nullptr;
      }
    }
    if (!texture_) {
      texture_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STREAMING,
                                   int(image.width), int(image.height));
    }
    SDL_UpdateTexture(texture_, nullptr, image.pixels.data(), int(image.width) * 4);
    SDL_RenderClear(renderer_);
    SDL_RenderCopy(renderer_, texture_, nullptr, nullptr);
  }
  void present() { SDL_RenderPresent(renderer_); }
  SDL_Renderer* renderer() const { return renderer_; }

 private:
  bool sdl_ = false;
  SDL_Window* window_ = nullptr;
  SDL_Renderer* renderer_ = nullptr;
  SDL_Texture* texture_ = nullptr;
};

// The camera and what the user does to it between two frames.
struct Controls {
  std::optional<CameraState> camera;        // known from the first frame on
  std::optional<CameraState> first_camera;  // R goes back to it
  bool running = true;
  bool dragging = false;
  Clock::time_point last_tick = Clock::now();

  // Handles the pending window events; returns whether the camera changed.
  bool handle_events() {
    bool changed = false;
    SDL_Event event;
    while (SDL_WaitEventTimeout(&event, 5)) {
      if (event.type == SDL_QUIT) running = false;
      if (event.type == SDL_KEYDOWN && event.key.keysym.sym == SDLK_ESCAPE) running = false;
      if (event.type == SDL_KEYDOWN && event.key.keysym.sym == SDLK_r && first_camera) {
        camera = first_camera;
        changed = true;
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
        changed = true;
      }
      if (!running) break;
    }
    return changed;
  }

  // Held keys move continuously, scaled by the time since the last tick (`now`); returns
  // whether the camera moved.
  bool apply_held_keys(Clock::time_point now, double speed) {
    const double dt = std::min(0.1, std::chrono::duration<double>(now - last_tick).count());
    last_tick = now;
    const Uint8* keys = SDL_GetKeyboardState(nullptr);
    if (!camera) return false;
    const double step = speed * dt, turn = 1.5 * dt;
    const double forward = (keys[SDL_SCANCODE_W] - keys[SDL_SCANCODE_S]) * step;
    const double right = (keys[SDL_SCANCODE_D] - keys[SDL_SCANCODE_A]) * step;
    const double up = (keys[SDL_SCANCODE_E] - keys[SDL_SCANCODE_Q]) * step;
    const double yaw = (keys[SDL_SCANCODE_RIGHT] - keys[SDL_SCANCODE_LEFT]) * turn;
    const double pitch = (keys[SDL_SCANCODE_UP] - keys[SDL_SCANCODE_DOWN]) * turn;
    if (forward == 0 && right == 0 && up == 0 && yaw == 0 && pitch == 0) return false;
    camera->move(forward, right, up);
    camera->yaw += yaw;
    camera->pitch = std::clamp(camera->pitch + pitch, -1.5, 1.5);
    return true;
  }
};

// Frames per second over the last half second or more.
class FpsCounter {
 public:
  void count(Clock::time_point now) {
    ++frames_;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (elapsed >= 0.5) {
      fps_ = frames_ / elapsed;
      frames_ = 0;
      start_ = now;
    }
  }
  double fps() const { return fps_; }

 private:
  Clock::time_point start_ = Clock::now();
  int frames_ = 0;
  double fps_ = 0.0;
};

v1::StreamFramesRequest stream_request(const ViewerOptions& options, const std::string& session) {
  v1::StreamFramesRequest request;
  request.set_session_id(session);
  request.mutable_settings()->set_width(uint32_t(options.width));
  request.mutable_settings()->set_height(uint32_t(options.height));
  request.mutable_settings()->set_jpeg_quality(uint32_t(options.quality));
  request.set_max_fps(float(options.max_fps));
  return request;
}

// Shows `session`'s frames until the window closes, the stream ends or --frames were shown,
// sending the camera moves the user makes; prints a JSON summary at the end.
Status show_stream(ViewerWindow& window, const ViewerOptions& options, const std::string& session) {
  ViewerLink link(options.connection, stream_request(options, session));
  Controls controls;
  FpsCounter fps;
  encode::ImageRgba8 shown;
  int64_t frames_shown = 0;
  Status result = ok_status();
  const bool last_frame_screenshot = !options.screenshot.empty() && options.max_frames > 0;
  while (controls.running) {
    bool camera_changed = controls.handle_events();
    const auto now = Clock::now();
    camera_changed = controls.apply_held_keys(now, options.speed) || camera_changed;
    if (camera_changed && controls.camera) link.move_camera(controls.camera->to_camera());

    if (auto frame = link.take_frame()) {
      if (!controls.camera) {
        controls.camera = CameraState::from(frame->info.camera());
        controls.first_camera = controls.camera;
      }
      fps.count(now);
      shown = std::move(frame->image);
      const int scale = shown.width >= 480 ? 2 : 1;
      draw_text(shown, 4 * scale, 4 * scale, stats_line(fps.fps(), link.stats(), frame->info),
                scale);
      window.draw(shown);
      if (last_frame_screenshot && frames_shown + 1 == options.max_frames) {
        // Read back before presenting: the back buffer is defined only until then.
        result = save_screenshot(window.renderer(), shown, options.screenshot);
      }
      window.present();
      ++frames_shown;
      if (options.max_frames > 0 && frames_shown >= options.max_frames) controls.running = false;
    }
    if (link.ended()) {
      const grpc::Status status = link.status();
      if (!status.ok()) {
        result = unavailable(std::string("stream: ") + status_code_name(status.error_code()) +
                             ": " + status.error_message());
      }
      controls.running = false;
    }
  }
  if (!options.screenshot.empty() &&
      (options.max_frames == 0 || frames_shown < options.max_frames) && result.ok() &&
      !shown.pixels.empty()) {
    result = encode::write_image(options.screenshot, shown);
  }
  std::printf("{\"frames_shown\": %lld, \"fps\": %.2f, \"latency_ms\": %.1f}\n",
              static_cast<long long>(frames_shown), fps.fps(), link.stats().latency_ms);
  return result;
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(const std::optional<ViewerOptions> options, parse_options(argc, argv));
  if (!options) return ok_status();  // --help
  std::string session = options->session;
  std::unique_ptr<OwnedSession> owned;
  if (session.empty()) {
    DDGI_ASSIGN_OR_RETURN(session, create_session(options->connection, options->scene));
    owned = std::make_unique<OwnedSession>(options->connection, session);
  }
  ViewerWindow window;
  DDGI_TRY(window.open(int(options->width), int(options->height)));
  return show_stream(window, *options, session);
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
