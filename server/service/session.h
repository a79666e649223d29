// One session: a scene on the GPU, its irradiance field and lights, and the views clients
// attached to it. A frame loop thread owns all of it: RPCs never touch GPU state, they queue
// commands that the loop applies between frames in arrival order. Each loop iteration applies
// the queued commands, updates the field once, renders every view someone is waiting for and
// hands the images to the encoder.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "gi/gi_stack.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "service/convert.h"
#include "service/frame_encoder.h"
#include "service/frame_stream.h"
#include "service/limits.h"
#include "service/metrics.h"
#include "vk/context.h"

namespace ddgi::service {

// Finishes one RPC; called exactly once, from the loop thread or an encoder thread.
using Completion = std::function<void(const Status&)>;

// What the session's scene comes from and how its field starts.
struct SceneRequest {
  std::string label;            // "cornell_box" or "upload:<bytes>"
  std::string path;             // a library file; empty for an upload
  std::vector<uint8_t> upload;  // the .glb bytes of an upload
  uint32_t warmup_updates = 16;
};

struct SessionOptions {
  bool gi = true;
  DirectMode direct_mode = DirectMode::kTracedShadows;
  std::vector<std::string> field_assignments;  // "name=value", applied over the scene's defaults
  // Shadow-field "name=value" over the grid fitted to the scene; the field exists only in the
  // shadow-field and AO direct modes.
  std::vector<std::string> shadow_assignments;
};

// What every session shares with the rest of the server.
struct SessionEnv {
  vk::Context* context = nullptr;
  const ServiceLimits* limits = nullptr;
  Metrics* metrics = nullptr;
  FrameEncoder* encoder = nullptr;
  // Called on the loop thread after the loop ended and every GPU object is freed.
  std::function<void()> on_loop_exit;
};

class Session : public std::enable_shared_from_this<Session> {
 public:
  static std::shared_ptr<Session> create(std::string id, SessionEnv env, SessionOptions options);
  // Starts the frame loop; its first command loads the scene and completes `done`.
  void start(SceneRequest scene, v1::SessionInfo* reply, Completion done);
  ~Session();

  const std::string& id() const { return id_; }
  v1::SessionSummary summary() const;

  // Every request below is queued; `done` runs once it was applied (or failed). `reply` must
  // stay valid until then (it belongs to the RPC).
  void load_scene(SceneRequest scene, v1::SessionInfo* reply, Completion done);
  void get_info(v1::SessionInfo* reply, Completion done);
  void create_view(ViewConfig config, std::optional<v1::Camera> camera, v1::ViewInfo* reply,
                   Completion done);
  void update_view(std::string view_id, v1::ViewSettings settings, v1::ViewInfo* reply,
                   Completion done);
  void delete_view(std::string view_id, Completion done);
  void set_camera(std::string view_id, v1::Camera camera, v1::ViewInfo* reply, Completion done);
  void add_light(v1::Light light, v1::LightReply* reply, Completion done);
  void update_light(uint32_t light_id, v1::Light light, v1::LightReply* reply, Completion done);
  void remove_light(uint32_t light_id, v1::LightReply* reply, Completion done);
  void set_instance_transform(uint32_t index, glm::mat4 transform, v1::InstanceReply* reply,
                              Completion done);
  void get_field_params(v1::FieldKind kind, v1::FieldParams* reply, Completion done);
  void set_field_params(v1::FieldKind kind, std::vector<std::string> assignments,
                        v1::FieldParams* reply, Completion done);
  // An existing view (view_id) or a one-off view made of config and camera.
  void render_frame(std::string view_id, ViewConfig config, std::optional<v1::Camera> camera,
                    FrameWaiter waiter);
  void attach_stream(std::string view_id, ViewConfig config, std::optional<v1::Camera> camera,
                     std::shared_ptr<FrameStreamState> stream);
  void detach_stream(std::shared_ptr<FrameStreamState> stream);
  void query(std::vector<IrradianceQuery> points, v1::QueryIrradianceReply* reply, Completion done);
  // Reads an atlas and encodes it; `done` gets the metadata and bytes.
  using AtlasDone = std::function<void(Result<std::pair<v1::AtlasMetadata, std::vector<uint8_t>>>)>;
  void dump_atlas(v1::AtlasKind kind, v1::AtlasFormat format, AtlasDone done);

  // Ends the loop: queued commands fail with UNAVAILABLE, streams end with OK, GPU memory is
  // freed, then `on_stopped` runs (on the loop thread).
  void stop(std::function<void()> on_stopped);

 private:
  struct Command {
    std::function<void(Completion)> run;  // on the loop thread; must complete exactly once
    Completion done;
    uint64_t seq = 0;
    int64_t arrival_unix_us = 0;
    bool changes_state = false;  // counts as "the newest applied command" for frames
  };
  struct ViewState {
    std::string id;
    ViewConfig config;
    Camera camera;
    std::unique_ptr<FrameTarget> target;  // made at its first frame, remade when resized
    std::vector<std::shared_ptr<FrameStreamState>> streams;
    std::vector<FrameWaiter> waiters;
    bool owned_by_stream = false;  // deleted when its stream ends
    bool one_off = false;          // deleted after its next frame
    uint64_t seq = 0;              // the command that last changed it
  };
  struct LightSlot {
    uint32_t id = 0;
    Light light;
  };

  Session(std::string id, SessionEnv env, SessionOptions options);
  // Queues a command; after stop() it fails at once.
  void enqueue(bool changes_state, std::function<void(Completion)> run, Completion done);
  // Shorthand for commands that finish when `run` returns.
  void enqueue_sync(bool changes_state, std::function<Status()> run, Completion done);

  void loop();
  void produce_frame();
  void teardown();
  Status load(const SceneRequest& request);
  Result<ViewState*> find_view(const std::string& view_id);
  Result<ViewState*> add_view(ViewConfig config, const std::optional<v1::Camera>& camera,
                              bool counts_against_limit);
  void erase_view(const std::string& view_id);
  Status upload_lights();
  void fill_info(v1::SessionInfo* info) const;
  void fill_view(const ViewState& view, v1::ViewInfo* info) const;
  void fill_field(v1::FieldParams* params) const;
  void fill_shadow_field(v1::FieldParams* params) const;
  // FAILED_PRECONDITION when the session lacks the field of `kind`.
  Status require_field(v1::FieldKind kind) const;
  // Renders `view` into its target (made or remade to size first), after the GI stack's update
  // when `field_due`. The session's renderer is built at the first frame after a scene load.
  Result<FrameResult> render_view(ViewState& view, const FrameSettings& settings, bool field_due);
  IrradianceField* field() const { return gi_ ? gi_->field() : nullptr; }
  ShadowField* shadow_field() const { return gi_ ? gi_->shadow_field() : nullptr; }
  void fill_light(const LightSlot& slot, v1::LightEntry* entry) const;
  void fail_view(ViewState& view, const Error& error);
  std::string new_view_id();
  void update_summary();

  const std::string id_;
  SessionEnv env_;
  SessionOptions options_;
  const int64_t created_unix_us_;

  // Shared with RPC threads.
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Command> queue_;
  uint64_t next_seq_ = 1;
  bool stopping_ = false;
  std::vector<std::function<void()>> on_stopped_;
  v1::SessionSummary summary_;

  // Owned by the loop thread.
  std::string scene_label_;
  std::vector<std::string> warnings_;
  Camera default_camera_;
  std::unique_ptr<GiStack> gi_;
  std::unique_ptr<Renderer> renderer_;  // kernels built once per scene, shared by every view
  std::vector<LightSlot> lights_;
  uint32_t next_light_id_ = 0;
  std::map<std::string, ViewState> views_;
  uint64_t next_view_number_ = 1;
  uint64_t frame_index_ = 0;
  uint64_t applying_seq_ = 0;
  uint64_t last_applied_seq_ = 0;
  int64_t last_applied_arrival_us_ = 0;
  std::chrono::steady_clock::time_point last_frame_start_{};
};

int64_t unix_micros();

}  // namespace ddgi::service
