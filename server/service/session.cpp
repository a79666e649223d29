// A session's commands: each public method queues one on the session's loop, where it acts on
// the session's state and fills its reply through convert.h (service/session.h). The frames
// are in session_frames.cpp. Commands that touch the scene's or the fields' GPU state (host
// writes, descriptor updates, buffers replaced) first finish the frames in flight; camera and
// view commands do not, so a moving camera keeps the frames pipelined.
#include "service/session.h"

#include <thread>

#include "core/log.h"
#include "gi/field_params.h"
#include "gi/shadow_params.h"
#include "service/atlas_export.h"
#include "service/grpc_status.h"
#include "service/scene_export.h"
#include "service/text.h"

namespace ddgi::service {

Session::Session(std::string id, SessionEnv env, SessionOptions options)
    : env_(std::move(env)),
      state_(id, unix_micros(), std::move(options), *env_.limits, *env_.metrics),
      pacer_(env_.submit_ahead),
      one_off_slots_(id, env_.limits->max_one_off_frames),
      loop_(id, env_.limits->max_fps, *this) {
  to_proto(state_, 0, &summary_);
}

Session::~Session() = default;

std::shared_ptr<Session> Session::create(std::string id, SessionEnv env, SessionOptions options) {
  return std::shared_ptr<Session>(new Session(std::move(id), std::move(env), std::move(options)));
}

void Session::start(SceneRequest scene, v1::SessionInfo* reply, Completion done) {
  auto request = std::make_shared<SceneRequest>(std::move(scene));
  loop_.enqueue_sync(
      true,
      [this, request, reply]() -> Status {
        DDGI_TRY(load(*request));
        to_proto(state_, loop_.frames(), loop_.applying_seq(), reply);
        return ok_status();
      },
      std::move(done));
  loop_.start(shared_from_this(), env_.on_loop_exit);
}

void Session::stop(std::function<void()> on_stopped, std::optional<Error> reason) {
  loop_.stop(std::move(on_stopped), std::move(reason));
}

v1::SessionSummary Session::summary() const {
  std::lock_guard<std::mutex> lock(summary_mutex_);
  return summary_;
}

// ---- Scene --------------------------------------------------------------------------------------

Status Session::load(const SceneRequest& request) {
  finish_frames();
  DDGI_ASSIGN_OR_RETURN(std::unique_ptr<SessionScene> scene,
                        SessionScene::load(*env_.context, request, state_.options, *env_.limits,
                                           *env_.budget, state_.id));
  if (scene->field()) env_.metrics->field_updates.fetch_add(request.warmup_updates);
  // The old scene (its renderer first) goes once the new one is on the GPU. View targets do
  // not depend on the scene and stay.
  forget_world_cache();
  state_.scene = std::move(scene);
  for (auto& [view_id, view] : state_.views.all()) view.camera = state_.scene->default_camera();
  // The calibration runs beside the frames; its choice is adopted on this loop once it lands.
  state_.scene->start_calibration(*env_.budget, [weak = weak_from_this()] {
    if (const std::shared_ptr<Session> self = weak.lock()) self->adopt_calibration();
  });
  return ok_status();
}

void Session::adopt_calibration() {
  loop_.enqueue_sync(
      true,
      [this]() -> Status {
        if (!state_.scene) return ok_status();
        finish_frames();  // the field's parameters change under no frame in flight
        return state_.scene->adopt_calibration(state_.id);
      },
      [id = state_.id](const Status& status) {
        if (!status.ok()) {
          LOG_WARNING << "calibration not adopted session=" << id << ": " << status.error().message;
        }
      });
}

Status Session::check_view_config(const ViewConfig& config) const {
  if (config.view == View::kProbes && field() == nullptr) {
    return failed_precondition(
        "settings.view_mode VIEW_MODE_PROBES needs the irradiance field; "
        "session " +
        state_.id + " was created with gi false");
  }
  return ok_status();
}

Result<SessionScene*> Session::require_scene() {
  if (!state_.scene) return failed_precondition("session " + state_.id + " has no scene loaded");
  return state_.scene.get();
}

void Session::load_scene(SceneRequest scene, v1::SessionInfo* reply, Completion done) {
  auto request = std::make_shared<SceneRequest>(std::move(scene));
  loop_.enqueue_sync(
      true,
      [this, request, reply]() -> Status {
        DDGI_TRY(load(*request));
        to_proto(state_, loop_.frames(), loop_.applying_seq(), reply);
        return ok_status();
      },
      std::move(done));
}

void Session::get_info(v1::SessionInfo* reply, Completion done) {
  loop_.enqueue_sync(
      false,
      [this, reply]() -> Status {
        to_proto(state_, loop_.frames(), loop_.applying_seq(), reply);
        return ok_status();
      },
      std::move(done));
}

// ---- Views --------------------------------------------------------------------------------------

Result<Camera> Session::camera_or_default(const std::optional<v1::Camera>& camera) const {
  const Camera& base = state_.scene->default_camera();
  if (!camera) return base;
  return camera_from_proto(*camera, base);
}

void Session::create_view(ViewConfig config, std::optional<v1::Camera> camera, v1::ViewInfo* reply,
                          Completion done) {
  loop_.enqueue_sync(
      true,
      [this, config, camera, reply]() -> Status {
        DDGI_TRY(require_scene());
        DDGI_TRY(check_view_config(config));
        DDGI_ASSIGN_OR_RETURN(const Camera view_camera, camera_or_default(camera));
        DDGI_ASSIGN_OR_RETURN(SessionView * view,
                              state_.views.add(config, view_camera, loop_.applying_seq()));
        to_proto(*view, reply);
        return ok_status();
      },
      std::move(done));
}

void Session::update_view(std::string view_id, v1::ViewSettings settings, v1::ViewInfo* reply,
                          Completion done) {
  loop_.enqueue_sync(
      true,
      [this, view_id, settings, reply]() -> Status {
        DDGI_ASSIGN_OR_RETURN(SessionView * view, state_.views.find(view_id));
        ViewConfig next = view->config;
        DDGI_TRY(apply_view_settings(settings, *env_.limits, next));
        DDGI_TRY(check_view_config(next));
        view->config = next;
        view->seq = loop_.applying_seq();
        to_proto(*view, reply);
        return ok_status();
      },
      std::move(done));
}

void Session::delete_view(std::string view_id, Completion done) {
  loop_.enqueue_sync(
      true,
      [this, view_id]() -> Status {
        DDGI_TRY(state_.views.find(view_id));
        state_.views.erase(view_id);
        return ok_status();
      },
      std::move(done));
}

void Session::set_camera(std::string view_id, v1::Camera camera, v1::ViewInfo* reply,
                         Completion done) {
  loop_.enqueue_sync(
      true,
      [this, view_id, camera, reply]() -> Status {
        DDGI_ASSIGN_OR_RETURN(SessionView * view, state_.views.find(view_id));
        DDGI_ASSIGN_OR_RETURN(view->camera, camera_or_default(camera));
        view->seq = loop_.applying_seq();
        to_proto(*view, reply);
        return ok_status();
      },
      std::move(done));
}

// ---- Lights and instances -----------------------------------------------------------------------

Result<const LightSlot*> Session::find_light(uint32_t light_id) const {
  const LightSlot* slot = state_.scene ? state_.scene->lights().find(light_id) : nullptr;
  if (!slot) return not_found("session " + state_.id + " has no light " + std::to_string(light_id));
  return slot;
}

void Session::add_light(v1::Light light, v1::LightReply* reply, Completion done) {
  loop_.enqueue_sync(
      true,
      [this, light, reply]() -> Status {
        finish_frames();
        DDGI_ASSIGN_OR_RETURN(SessionScene * scene, require_scene());
        const uint32_t max_lights = env_.limits->max_lights;
        if (scene->lights().size() >= max_lights) {
          return resource_exhausted(
              "session " + state_.id + " already has " + std::to_string(scene->lights().size()) +
              " lights, the most allowed (--max-lights " + std::to_string(max_lights) + ")");
        }
        DDGI_ASSIGN_OR_RETURN(const Light value, light_from_proto(light, Light{}));
        DDGI_ASSIGN_OR_RETURN(const LightSlot added, scene->add_light(value));
        to_proto(added, loop_.applying_seq(), reply);
        return ok_status();
      },
      std::move(done));
}

void Session::update_light(uint32_t light_id, v1::Light light, v1::LightReply* reply,
                           Completion done) {
  loop_.enqueue_sync(
      true,
      [this, light_id, light, reply]() -> Status {
        finish_frames();
        DDGI_ASSIGN_OR_RETURN(const LightSlot* slot, find_light(light_id));
        DDGI_ASSIGN_OR_RETURN(const Light value, light_from_proto(light, slot->light));
        DDGI_ASSIGN_OR_RETURN(const LightSlot updated, state_.scene->update_light(light_id, value));
        to_proto(updated, loop_.applying_seq(), reply);
        return ok_status();
      },
      std::move(done));
}

void Session::remove_light(uint32_t light_id, v1::LightReply* reply, Completion done) {
  loop_.enqueue_sync(
      true,
      [this, light_id, reply]() -> Status {
        finish_frames();
        DDGI_TRY(find_light(light_id));
        DDGI_ASSIGN_OR_RETURN(const LightSlot removed, state_.scene->remove_light(light_id));
        to_proto(removed, loop_.applying_seq(), reply);
        return ok_status();
      },
      std::move(done));
}

void Session::set_instance_transform(uint32_t index, glm::mat4 transform, v1::InstanceReply* reply,
                                     Completion done) {
  loop_.enqueue_sync(
      true,
      [this, index, transform, reply]() -> Status {
        finish_frames();
        DDGI_ASSIGN_OR_RETURN(SessionScene * scene, require_scene());
        GpuScene& gpu_scene = scene->gpu_scene();
        const size_t instances = gpu_scene.scene().instances.size();
        if (index >= instances) {
          return not_found("session " + state_.id + " has no instance " + std::to_string(index) +
                           " (its scene has " + std::to_string(instances) + " instances)");
        }
        DDGI_TRY(gpu_scene.set_instance_transform(index, transform));
        to_proto(gpu_scene, index, loop_.applying_seq(), reply);
        return ok_status();
      },
      std::move(done));
}

// ---- Fields -------------------------------------------------------------------------------------

Status Session::require_field(v1::FieldKind kind) const {
  if (kind == v1::FIELD_KIND_SHADOW && !shadow_field()) {
    return failed_precondition("session " + state_.id +
                               " has no shadow field (create it with direct_mode SHADOW_FIELD "
                               "or AMBIENT_OCCLUSION)");
  }
  if (kind != v1::FIELD_KIND_SHADOW && !field()) {
    return failed_precondition("session " + state_.id +
                               " runs without GI (CreateSession gi=false): it has no field");
  }
  return ok_status();
}

void Session::get_field_params(v1::FieldKind kind, v1::FieldParams* reply, Completion done) {
  loop_.enqueue_sync(
      false,
      [this, kind, reply]() -> Status {
        finish_frames();
        DDGI_TRY(require_field(kind));
        if (kind == v1::FIELD_KIND_SHADOW) {
          to_proto(*shadow_field(), loop_.applying_seq(), reply);
        } else {
          to_proto(*state_.scene, loop_.applying_seq(), reply);
        }
        return ok_status();
      },
      std::move(done));
}

void Session::set_field_params(v1::FieldKind kind, std::vector<std::string> assignments,
                               v1::FieldParams* reply, Completion done) {
  loop_.enqueue_sync(
      true,
      [this, kind, assignments, reply]() mutable -> Status {
        finish_frames();
        DDGI_TRY(require_field(kind));
        if (kind == v1::FIELD_KIND_SHADOW) {
          ShadowFieldParams params = shadow_field()->params();
          DDGI_TRY(shadow_param_table().apply(params, assignments));
          DDGI_TRY(shadow_field()->set_params(params));
          to_proto(*shadow_field(), loop_.applying_seq(), reply);
        } else {
          DDGI_ASSIGN_OR_RETURN(const std::optional<double> budget_ms, take_budget(assignments));
          if (budget_ms) {
            // The rule's choice within the new budget, the request's other parameters over it.
            DDGI_TRY(
                state_.scene->set_field_budget(*budget_ms, assignments, *env_.budget, state_.id));
          } else {
            IrradianceFieldParams params = field()->params();
            DDGI_TRY(field_param_table().apply(params, assignments));
            DDGI_TRY(field()->set_params(params));
            state_.scene->end_budget();  // set by hand: no longer the rule's choice
          }
          to_proto(*state_.scene, loop_.applying_seq(), reply);
        }
        LOG_INFO << "field parameters changed session=" << state_.id
                 << " field=" << (kind == v1::FIELD_KIND_SHADOW ? "shadow" : "irradiance")
                 << " count=" << assignments.size();
        return ok_status();
      },
      std::move(done));
}

// ---- Frames, queries, atlases -------------------------------------------------------------------

Status Session::queue_one_off(const ViewConfig& config, const std::optional<v1::Camera>& camera,
                              FrameWaiter& waiter) {
  DDGI_TRY(require_scene());
  DDGI_TRY(check_view_config(config));
  DDGI_ASSIGN_OR_RETURN(const Camera one_off_camera, camera_or_default(camera));
  state_.one_offs.add(config, one_off_camera, std::move(waiter));
  return ok_status();
}

Status Session::queue_waiter(const std::string& view_id, FrameWaiter& waiter) {
  DDGI_ASSIGN_OR_RETURN(SessionView * view, state_.views.find(view_id));
  view->waiters.push_back(std::move(waiter));
  return ok_status();
}

void Session::render_frame(std::string view_id, ViewConfig config, std::optional<v1::Camera> camera,
                           FrameWaiter waiter) {
  if (view_id.empty()) {
    // Bounded before it is queued: a refused call costs the session nothing.
    const Status slot = one_off_slots_.take(waiter);
    if (!slot.ok()) {
      waiter(slot.error());
      return;
    }
  }
  auto shared_waiter = std::make_shared<FrameWaiter>(std::move(waiter));
  loop_.enqueue(
      false,
      [this, view_id, config, camera, shared_waiter](Completion finish) {
        const Status queued = view_id.empty() ? queue_one_off(config, camera, *shared_waiter)
                                              : queue_waiter(view_id, *shared_waiter);
        if (!queued.ok()) finish(queued);
      },
      [shared_waiter](const Status& status) {
        if (!status.ok()) (*shared_waiter)(status.error());
      });
}

void Session::attach_stream(std::string view_id, ViewConfig config,
                            std::optional<v1::Camera> camera,
                            std::shared_ptr<FrameStreamState> stream) {
  loop_.enqueue(
      false,
      [this, view_id, config, camera, stream](Completion finish) {
        Result<SessionView*> view = [&]() -> Result<SessionView*> {
          if (!view_id.empty()) return state_.views.find(view_id);
          DDGI_TRY(require_scene());
          DDGI_TRY(check_view_config(config));
          DDGI_ASSIGN_OR_RETURN(const Camera view_camera, camera_or_default(camera));
          DDGI_ASSIGN_OR_RETURN(SessionView * made,
                                state_.views.add(config, view_camera, loop_.applying_seq()));
          made->owned_by_stream = true;
          return made;
        }();
        if (!view.ok()) {
          finish(view.error());
          return;
        }
        (*view)->streams.push_back(stream);
        LOG_INFO << "stream attached session=" << state_.id << " view=" << (*view)->id;
      },
      [stream](const Status& status) {
        if (!status.ok()) stream->finish(to_grpc(status.error()));
      });
}

void Session::detach_stream(std::shared_ptr<FrameStreamState> stream) {
  loop_.enqueue(
      false,
      [this, stream](Completion finish) {
        state_.views.detach(stream);
        finish(ok_status());
      },
      [](const Status&) {});
}

void Session::attach_probe_stream(std::shared_ptr<ProbeStreamState> stream) {
  loop_.enqueue(
      false,
      [this, stream](Completion finish) {
        if (Status has_field = require_field(v1::FIELD_KIND_IRRADIANCE); !has_field.ok()) {
          finish(has_field);
          return;
        }
        state_.probe_streams.push_back(stream);
        LOG_INFO << "probe stream attached session=" << state_.id;
        finish(ok_status());
      },
      [stream](const Status& status) {
        if (!status.ok()) stream->finish(to_grpc(status.error()));
      });
}

void Session::detach_probe_stream(std::shared_ptr<ProbeStreamState> stream) {
  loop_.enqueue(
      false,
      [this, stream](Completion finish) {
        std::erase(state_.probe_streams, stream);
        finish(ok_status());
      },
      [](const Status&) {});
}

void Session::query(std::vector<IrradianceQuery> points, std::optional<uint32_t> volume,
                    v1::QueryIrradianceReply* reply, Completion done) {
  auto shared_points = std::make_shared<std::vector<IrradianceQuery>>(std::move(points));
  loop_.enqueue_sync(
      false,
      [this, shared_points, volume, reply]() -> Status {
        finish_frames();
        DDGI_TRY(require_field(v1::FIELD_KIND_IRRADIANCE));
        DDGI_ASSIGN_OR_RETURN(const std::vector<glm::vec3> values,
                              field()->query(*shared_points, volume));
        to_proto(values, field()->updates(), reply);
        return ok_status();
      },
      std::move(done));
}

void Session::dump_atlas(const AtlasRequest& request, AtlasDone done) {
  auto shared_done = std::make_shared<AtlasDone>(std::move(done));
  loop_.enqueue(
      false,
      [this, request, shared_done](Completion) {
        finish_frames();
        auto result = [&]() -> Result<std::pair<v1::AtlasMetadata, std::vector<uint8_t>>> {
          const bool shadow_kind = request.kind == v1::ATLAS_KIND_SHADOW ||
                                   request.kind == v1::ATLAS_KIND_SHADOW_MOMENTS;
          DDGI_TRY(require_field(shadow_kind ? v1::FIELD_KIND_SHADOW : v1::FIELD_KIND_IRRADIANCE));
          DDGI_ASSIGN_OR_RETURN(auto dump,
                                read_atlas(*env_.context, field(), shadow_field(), request));
          DDGI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, encode_atlas(dump.second, dump.first));
          return std::make_pair(std::move(dump.first), std::move(bytes));
        }();
        (*shared_done)(std::move(result));
      },
      [shared_done](const Status& status) {
        if (!status.ok()) (*shared_done)(status.error());
      });
}

// ---- Scene export -------------------------------------------------------------------------------

void Session::export_scene(SceneDone done) {
  auto shared_done = std::make_shared<SceneDone>(std::move(done));
  loop_.enqueue(
      false,
      [this, shared_done](Completion) {
        auto scene = require_scene();
        if (!scene.ok()) return (*shared_done)(scene.error());
        auto copy = std::make_shared<const Scene>((*scene)->gpu_scene().scene());
        auto lights = std::make_shared<const std::vector<LightSlot>>((*scene)->lights().slots());
        std::string label = (*scene)->label();
        std::thread([copy, lights, label, shared_done] {
          auto exported = export_glb(*copy, *lights);
          if (!exported.ok()) return (*shared_done)(exported.error());
          exported->metadata.set_scene(label);
          (*shared_done)(std::make_pair(std::move(exported->metadata), std::move(exported->glb)));
        }).detach();
      },
      [shared_done](const Status& status) {
        if (!status.ok()) (*shared_done)(status.error());
      });
}

}  // namespace ddgi::service
