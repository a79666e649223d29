// One session: a scene on the GPU, its fields and lights, and the views clients attached to it.
// Three parts: a SessionLoop (session_loop.h) runs the queued commands in arrival order on its
// own thread, paces frames and orders teardown; the SessionState (session_state.h: the loaded
// scene, the views, the one-off frames) is what the commands act on; convert.h turns that state
// into replies and frames. RPCs never touch GPU state: each method here queues a command, and
// each loop iteration applies the queued commands, updates the fields once, submits a frame of
// every view someone is waiting for, then reads back the previous iteration's frames (still on
// the GPU while this one's were recorded) and hands their images to the encoder.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "service/atlas_export.h"
#include "service/convert.h"
#include "service/frame_encoder.h"
#include "service/frame_record.h"
#include "service/frame_stream.h"
#include "service/limits.h"
#include "service/metrics.h"
#include "service/one_off_frames.h"
#include "service/session_loop.h"
#include "service/session_scene.h"
#include "service/session_state.h"
#include "service/session_view.h"
#include "service/submit_pacer.h"
#include "vk/context.h"

namespace ddgi::service {

// What every session shares with the rest of the server.
struct SessionEnv {
  vk::Context* context = nullptr;
  const ServiceLimits* limits = nullptr;
  Metrics* metrics = nullptr;
  FrameEncoder* encoder = nullptr;
  BudgetService* budget = nullptr;  // the time budget's settings and calibration cache
  SubmitPacer::Millis submit_ahead{kDefaultSubmitAheadMs};  // ServerOptions::submit_ahead_ms
  // Called on the loop thread after the loop ended and every GPU object is freed.
  std::function<void()> on_loop_exit;
};

class Session : public std::enable_shared_from_this<Session>, private SessionLoop::Owner {
 public:
  static std::shared_ptr<Session> create(std::string id, SessionEnv env, SessionOptions options);
  // Starts the frame loop; its first command loads the scene and completes `done`.
  void start(SceneRequest scene, v1::SessionInfo* reply, Completion done);
  ~Session() override;

  const std::string& id() const { return state_.id; }
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
  // StreamProbes: the stream gets a snapshot of the field after every update from now on.
  void attach_probe_stream(std::shared_ptr<ProbeStreamState> stream);
  void detach_probe_stream(std::shared_ptr<ProbeStreamState> stream);
  // `volume`: one volume of the field alone (QueryIrradianceRequest.volume), else the blend.
  void query(std::vector<IrradianceQuery> points, std::optional<uint32_t> volume,
             v1::QueryIrradianceReply* reply, Completion done);
  // Reads an atlas and encodes it; `done` gets the metadata and bytes.
  using AtlasDone = std::function<void(Result<std::pair<v1::AtlasMetadata, std::vector<uint8_t>>>)>;
  void dump_atlas(const AtlasRequest& request, AtlasDone done);
  // ExportScene: copies the scene and its lights on the loop, then writes the .glb on a thread
  // of its own (large textured scenes take seconds; the session's frames go on meanwhile).
  using SceneDone = std::function<void(Result<std::pair<v1::SceneMetadata, std::vector<uint8_t>>>)>;
  void export_scene(SceneDone done);

  // Ends the loop: queued commands fail with UNAVAILABLE, streams end with OK (or both with
  // `reason`, when given: a lost device), GPU memory is freed, then `on_stopped` runs (on the
  // loop thread).
  void stop(std::function<void()> on_stopped, std::optional<Error> reason = std::nullopt);

 private:
  // One loop iteration's frames share one update of the fields: recorded with the first frame
  // submitted, reported by every frame of the iteration (its times are known once that first
  // frame is read back, which is before the others: frames are finished in submission order).
  struct FrameBatch {
    uint64_t index = 0;
    CommandStamp last_applied;
    bool field_due = false;
    std::vector<vk::PassTime> gi_passes;
    double gi_ms = 0.0;
  };
  // A frame submitted and not yet read back, and what its encoder job needs besides the image.
  struct InFlightFrame {
    std::shared_ptr<FrameBatch> batch;
    bool carries_update = false;          // the batch's field update was recorded with this frame
    std::shared_ptr<FrameTarget> target;  // a view's: kept until read back (before `pending`)
    PendingFrame pending;
    FrameRecord record;
    std::unique_ptr<EncodeJob> job;  // its key, streams and waiters; the image comes at the end
    std::chrono::steady_clock::time_point start;
  };

  Session(std::string id, SessionEnv env, SessionOptions options);

  // SessionLoop::Owner (session_frames.cpp), on the loop thread.
  bool wants_frame() override;
  void produce_frame(uint64_t index, const CommandStamp& last_applied) override;
  void after_iteration() override;
  void finish_frames() override;
  std::chrono::steady_clock::time_point next_submit_time() override;
  void tear_down(const Error& why, bool failed) override;

  // Frames (session_frames.cpp).
  // Submits a frame of every view someone waits for (into in_flight_).
  void render_views(const std::shared_ptr<FrameBatch>& batch);
  // One-off frames share targets per size: each is submitted and finished in turn, after the
  // frames in flight.
  void render_one_offs(const std::shared_ptr<FrameBatch>& batch);
  // Submits one frame of `config` and `camera` into `target`, with the batch's field update
  // when it is still due. The job has no key, streams or waiters yet; `view_id` is empty for a
  // one-off frame.
  Result<InFlightFrame> submit_frame(const std::shared_ptr<FrameBatch>& batch,
                                     const std::string& view_id, const ViewConfig& config,
                                     const Camera& camera, FrameTarget& target);
  // Reads a frame back and hands it to the encoder, or fails its streams and waiters; returns
  // its GPU time (0 if it failed).
  SubmitPacer::Millis deliver(InFlightFrame& frame);
  // Delivers the frames in flight of batches before `index`, oldest first, and tells the pacer
  // when the GPU was done with them: when the newest one's wait returned. `newest_first`: that
  // wait comes before any readback (each older frame then waits for the newest; else each is
  // read back as soon as it is done and the time comes after the older ones' copies).
  void deliver_older_than(uint64_t index, bool newest_first);
  // After an iteration's frames: updates the field if no frame did, and offers its snapshot to
  // every probe stream (the frames are finished first: the snapshot reads the field back).
  void stream_probes(const std::shared_ptr<FrameBatch>& batch);
  // Waits until the GPU is done with every frame in flight (reading nothing back).
  Status wait_for_frames_on_gpu();
  // Adds what the scene's world cache did since the last report to the server's metrics (after
  // a finished frame); forget_world_cache() takes its live entries off before the scene goes.
  void report_world_cache();
  void forget_world_cache();

  // Commands' pieces (session.cpp), on the loop thread.
  Status load(const SceneRequest& request);
  // Queues the adoption of the scene's finished calibration (called from the calibrator).
  void adopt_calibration();
  Result<SessionScene*> require_scene();
  // FAILED_PRECONDITION when the session lacks the field of `kind`.
  Status require_field(v1::FieldKind kind) const;
  // FAILED_PRECONDITION when a view's settings need what the session lacks (the probes view
  // needs the irradiance field).
  Status check_view_config(const ViewConfig& config) const;
  Result<Camera> camera_or_default(const std::optional<v1::Camera>& camera) const;
  Result<const LightSlot*> find_light(uint32_t light_id) const;
  // A RenderFrame's waiter joins the next frame: of a one-off view, or of the view `view_id`.
  // `waiter` is taken only on success.
  Status queue_one_off(const ViewConfig& config, const std::optional<v1::Camera>& camera,
                       FrameWaiter& waiter);
  Status queue_waiter(const std::string& view_id, FrameWaiter& waiter);
  IrradianceField* field() const { return state_.scene ? state_.scene->field() : nullptr; }
  ShadowField* shadow_field() const {
    return state_.scene ? state_.scene->shadow_field() : nullptr;
  }

  SessionEnv env_;
  // Owned by the loop thread.
  SessionState state_;
  std::deque<InFlightFrame> in_flight_;      // in submission order; after state_, freed before it
  SubmitPacer pacer_;                        // when in_flight_ wants the next batch
  WorldCacheCounters world_cache_reported_;  // the scene's cache's counts already in the metrics
  // Shared with RPC threads.
  mutable std::mutex summary_mutex_;
  v1::SessionSummary summary_;
  OneOffSlots one_off_slots_;
  SessionLoop loop_;
};

}  // namespace ddgi::service
