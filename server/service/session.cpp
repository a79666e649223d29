#include "service/session.h"

#include <algorithm>
#include <thread>

#include "core/log.h"
#include "gi/field_params.h"
#include "gi/shadow_params.h"
#include "gpu_scene/camera_fit.h"
#include "scene/gltf_loader.h"
#include "service/atlas_export.h"
#include "service/grpc_status.h"
#include "service/text.h"

namespace ddgi::service {

int64_t unix_micros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

Session::Session(std::string id, SessionEnv env, SessionOptions options)
    : id_(std::move(id)),
      env_(std::move(env)),
      options_(std::move(options)),
      created_unix_us_(unix_micros()) {
  summary_.set_session_id(id_);
  summary_.set_created_unix_us(created_unix_us_);
}

Session::~Session() = default;

std::shared_ptr<Session> Session::create(std::string id, SessionEnv env, SessionOptions options) {
  return std::shared_ptr<Session>(new Session(std::move(id), std::move(env), std::move(options)));
}

void Session::start(SceneRequest scene, v1::SessionInfo* reply, Completion done) {
  auto request = std::make_shared<SceneRequest>(std::move(scene));
  enqueue(
      true,
      [this, request, reply](Completion finish) {
        const Status status = load(*request);
        if (status.ok()) fill_info(reply);
        finish(status);
      },
      std::move(done));
  // The loop keeps the session alive until it has freed everything; nobody joins it, so no RPC
  // thread ever waits for a frame to finish.
  std::thread([self = shared_from_this()] { self->loop(); }).detach();
}

void Session::enqueue(bool changes_state, std::function<void(Completion)> run, Completion done) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!stopping_) {
      queue_.push_back(
          Command{std::move(run), std::move(done), next_seq_++, unix_micros(), changes_state});
      wake_.notify_one();
      return;
    }
  }
  done(unavailable("session " + id_ + " is closing"));
}

void Session::enqueue_sync(bool changes_state, std::function<Status()> run, Completion done) {
  enqueue(
      changes_state, [run = std::move(run)](Completion finish) { finish(run()); }, std::move(done));
}

void Session::stop(std::function<void()> on_stopped) {
  std::lock_guard<std::mutex> lock(mutex_);
  stopping_ = true;
  if (on_stopped) on_stopped_.push_back(std::move(on_stopped));
  wake_.notify_one();
}

v1::SessionSummary Session::summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return summary_;
}

// ---- The frame loop -----------------------------------------------------------------------------

void Session::loop() {
  LOG_INFO << "session loop started session=" << id_;
  const auto interval = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / env_.limits->max_fps));
  auto wants_frame = [this] {
    for (const auto& [id, view] : views_) {
      if (!view.waiters.empty()) return true;
      for (const auto& stream : view.streams) {
        if (!stream->ended()) return true;
      }
    }
    return false;
  };
  while (true) {
    std::deque<Command> batch;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      while (!stopping_ && queue_.empty()) {
        if (!wants_frame()) {
          wake_.wait(lock);
          continue;
        }
        const auto next = last_frame_start_ + interval;
        if (std::chrono::steady_clock::now() >= next) break;
        wake_.wait_until(lock, next);
      }
      if (stopping_) break;
      batch.swap(queue_);
    }
    for (Command& command : batch) {
      applying_seq_ = command.seq;
      if (command.changes_state) {
        last_applied_seq_ = command.seq;
        last_applied_arrival_us_ = command.arrival_unix_us;
      }
      command.run(std::move(command.done));
    }
    if (wants_frame() && std::chrono::steady_clock::now() >= last_frame_start_ + interval) {
      produce_frame();
    }
    update_summary();
    env_.context->collect_garbage();
  }
  teardown();
}

void Session::produce_frame() {
  last_frame_start_ = std::chrono::steady_clock::now();
  ++frame_index_;
  // One update of each field per frame, recorded with the first view, shared by every view.
  bool field_due = field() != nullptr || shadow_field() != nullptr;
  std::vector<vk::PassTime> gi_passes;
  double gi_ms = 0.0;
  std::vector<std::string> done_views;
  for (auto& [view_id, view] : views_) {
    std::erase_if(view.streams, [](const auto& stream) { return stream->ended(); });
    if (view.streams.empty() && view.waiters.empty()) continue;
    FrameSettings settings;
    settings.width = view.config.width;
    settings.height = view.config.height;
    settings.camera = view.camera;
    settings.direct_mode = options_.direct_mode;
    settings.view = view.config.view;
    settings.tonemap = view.config.tonemap;
    settings.exposure = view.config.exposure;
    settings.read_radiance = false;  // views stream JPEG: only the 8-bit image is encoded
    const auto start = std::chrono::steady_clock::now();
    Result<FrameResult> frame = render_view(view, settings, field_due);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!frame.ok()) {
      LOG_WARNING << "render failed session=" << id_ << " view=" << view_id << ": "
                  << frame.error().message;
      fail_view(view, frame.error());
      if (view.one_off || view.owned_by_stream) done_views.push_back(view_id);
      continue;
    }
    std::vector<vk::PassTime> view_passes;
    for (const vk::PassTime& pass : frame->pass_times) {
      const bool gi_pass = pass.group == vk::PassGroup::kIrradianceField ||
                           pass.group == vk::PassGroup::kShadowField;
      if (gi_pass) {
        gi_passes.push_back(pass);
        gi_ms += pass.milliseconds;
      } else {
        view_passes.push_back(pass);
      }
    }
    if (field_due) {
      field_due = false;
      env_.metrics->field_updates.fetch_add(1);
      env_.metrics->gi_update_seconds.observe(gi_ms * 1e-3);
    }
    env_.metrics->frames_rendered.fetch_add(1);
    env_.metrics->frame_seconds.observe(seconds);

    auto job = std::make_unique<EncodeJob>();
    job->view_key = id_ + "/" + view_id;
    job->image = encode::ImageRgba8{frame->width, frame->height, std::move(frame->ldr)};
    job->quality = view.config.jpeg_quality;
    job->max_frame_bytes = env_.limits->max_message_bytes;
    v1::Frame& out = job->frame;
    out.set_session_id(id_);
    out.set_view_id(view.one_off ? "" : view_id);
    out.set_frame_index(frame_index_);
    out.set_width(frame->width);
    out.set_height(frame->height);
    to_proto(view.camera, out.mutable_camera());
    double gpu_ms = 0.0;
    for (const auto* passes : {&gi_passes, &view_passes}) {
      for (const vk::PassTime& pass : *passes) {
        auto* p = out.add_passes();
        p->set_name(pass.name);
        p->set_milliseconds(pass.milliseconds);
        gpu_ms += pass.milliseconds;
      }
    }
    out.set_gpu_ms(gpu_ms);
    out.set_gi_update_ms(gi_ms);
    out.set_last_command_seq(last_applied_seq_);
    out.set_last_command_arrival_unix_us(last_applied_arrival_us_);
    out.set_rendered_unix_us(unix_micros());
    out.set_field_updates(field()          ? field()->updates()
                          : shadow_field() ? shadow_field()->updates()
                                           : 0);
    job->streams = view.streams;
    job->waiters = std::move(view.waiters);
    view.waiters.clear();
    env_.encoder->submit(std::move(job));
    if (view.one_off) done_views.push_back(view_id);
  }
  for (const std::string& view_id : done_views) erase_view(view_id);
}

Result<FrameResult> Session::render_view(ViewState& view, const FrameSettings& settings,
                                         bool field_due) {
  if (!renderer_) {
    DDGI_ASSIGN_OR_RETURN(renderer_,
                          Renderer::create(*env_.context, gi_->scene(), field(),
                                           env_.context->default_backend(), shadow_field()));
  }
  if (!view.target || view.target->width() != settings.width ||
      view.target->height() != settings.height) {
    view.target.reset();  // first, so that the budget sees only the new target
    DDGI_ASSIGN_OR_RETURN(view.target,
                          FrameTarget::create(*env_.context, settings.width, settings.height));
  }
  std::vector<vk::Pass> update;
  if (field_due) {
    DDGI_ASSIGN_OR_RETURN(update, gi_->frame_update(settings.direct_mode, {}));
  }
  return renderer_->render(settings, *view.target, update);
}

void Session::teardown() {
  std::deque<Command> rest;
  std::vector<std::function<void()>> on_stopped;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    rest.swap(queue_);
  }
  const Error closed = unavailable("session " + id_ + " was closed");
  for (Command& command : rest) command.done(closed);
  for (auto& [view_id, view] : views_) {
    for (auto& stream : view.streams) stream->finish(grpc::Status::OK);  // a clean end
    for (auto& waiter : view.waiters) waiter(closed);
    if (!view.one_off) env_.metrics->views.fetch_sub(1);
  }
  views_.clear();
  renderer_.reset();
  gi_.reset();
  env_.context->collect_garbage();
  env_.metrics->sessions.fetch_sub(1);
  LOG_INFO << "session closed session=" << id_ << " frames=" << frame_index_;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    on_stopped.swap(on_stopped_);
  }
  for (auto& callback : on_stopped) callback();
  if (env_.on_loop_exit) env_.on_loop_exit();
}

void Session::update_summary() {
  uint32_t views = 0, streams = 0;
  for (const auto& [id, view] : views_) {
    if (!view.one_off) ++views;
    streams += static_cast<uint32_t>(view.streams.size());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  summary_.set_scene(scene_label_);
  summary_.set_views(views);
  summary_.set_streams(streams);
  summary_.set_frames(frame_index_);
}

// ---- Scene
// ----------------------------------------------------------------------------------------

Status Session::load(const SceneRequest& request) {
  SceneLimits limits;
  Result<Scene> scene = [&]() -> Result<Scene> {
    if (request.path.empty()) {
      limits.max_file_bytes = std::max<uint64_t>(env_.limits->max_upload_bytes, 1024);
      return load_glb_from_memory(request.upload, request.label, limits);
    }
    return ::ddgi::load_scene(request.path, limits);
  }();
  if (!scene.ok()) return scene.error();
  for (const std::string& warning : scene->warnings) {
    LOG_WARNING << "scene warning session=" << id_ << " scene=" << request.label << ": " << warning;
  }
  vk::Context& context = *env_.context;
  DDGI_ASSIGN_OR_RETURN(
      const GiStackOptions options,
      fitted_gi_options(*scene, options_.gi, options_.direct_mode, options_.field_assignments,
                        options_.shadow_assignments, context.default_backend()));
  DDGI_ASSIGN_OR_RETURN(std::unique_ptr<GiStack> gi, GiStack::create(context, *scene, options));
  // As ddgi-render does: fast convergence first, then the configured hysteresis.
  DDGI_TRY(gi->warm_up(request.warmup_updates));
  if (gi->field()) env_.metrics->field_updates.fetch_add(request.warmup_updates);
  // The renderer points at the old scene and fields: drop it before those go. View targets do
  // not depend on the scene and stay.
  renderer_.reset();
  gi_ = std::move(gi);
  scene_label_ = request.label;
  warnings_ = scene->warnings;
  default_camera_ = default_camera(*scene);
  lights_.clear();
  for (const Light& light : gi_->scene().scene().lights) {
    lights_.push_back({static_cast<uint32_t>(lights_.size()), light});
  }
  next_light_id_ = static_cast<uint32_t>(lights_.size());
  for (auto& [view_id, view] : views_) view.camera = default_camera_;
  LOG_INFO << "scene loaded session=" << id_ << " scene=" << request.label
           << " triangles=" << gi_->scene().triangle_count() << " lights=" << lights_.size()
           << " gpu_bytes=" << gi_->scene().gpu_bytes() + (field() ? field()->gpu_bytes() : 0)
           << " warmup=" << (field() ? request.warmup_updates : 0);
  return ok_status();
}

void Session::load_scene(SceneRequest scene, v1::SessionInfo* reply, Completion done) {
  auto request = std::make_shared<SceneRequest>(std::move(scene));
  enqueue_sync(
      true,
      [this, request, reply]() -> Status {
        DDGI_TRY(load(*request));
        fill_info(reply);
        return ok_status();
      },
      std::move(done));
}

void Session::get_info(v1::SessionInfo* reply, Completion done) {
  enqueue_sync(
      false,
      [this, reply]() -> Status {
        fill_info(reply);
        return ok_status();
      },
      std::move(done));
}

void Session::fill_info(v1::SessionInfo* info) const {
  info->Clear();
  info->set_session_id(id_);
  info->set_scene(scene_label_);
  info->set_gi(field() != nullptr);
  info->set_frames(frame_index_);
  info->set_command_seq(applying_seq_);
  for (const std::string& warning : warnings_) info->add_warnings(warning);
  to_proto(default_camera_, info->mutable_default_camera());
  if (!gi_) return;
  info->set_triangles(gi_->scene().triangle_count());
  info->set_gpu_bytes(gi_->scene().gpu_bytes() + (field() ? field()->gpu_bytes() : 0) +
                      (shadow_field() ? shadow_field()->gpu_bytes() : 0));
  const auto& instances = gi_->scene().scene().instances;
  for (size_t i = 0; i < instances.size(); ++i) {
    auto* instance = info->add_instances();
    instance->set_index(static_cast<uint32_t>(i));
    instance->set_name(instances[i].name);
    to_proto(instances[i].transform, instance->mutable_transform());
  }
  for (const LightSlot& slot : lights_) fill_light(slot, info->add_lights());
  for (const auto& [view_id, view] : views_) {
    if (!view.one_off) fill_view(view, info->add_views());
  }
  if (field()) fill_field(info->mutable_field());
}

// ---- Views --------------------------------------------------------------------------------------

std::string Session::new_view_id() {
  std::string id = "v";  // appended: GCC 12 at -O3 warns falsely (-Wrestrict) on "v" + string
  return id.append(std::to_string(next_view_number_++));
}

Result<Session::ViewState*> Session::find_view(const std::string& view_id) {
  auto it = views_.find(view_id);
  if (it == views_.end() || it->second.one_off) {
    return not_found("session " + id_ + " has no view " + printable(view_id));
  }
  return &it->second;
}

Result<Session::ViewState*> Session::add_view(ViewConfig config,
                                              const std::optional<v1::Camera>& camera,
                                              bool counts_against_limit) {
  if (!gi_) return failed_precondition("session " + id_ + " has no scene loaded");
  if (counts_against_limit) {
    size_t count = 0;
    for (const auto& [id, view] : views_) count += view.one_off ? 0 : 1;
    if (count >= env_.limits->max_views_per_session) {
      return resource_exhausted("session " + id_ + " already has " + std::to_string(count) +
                                " views, the most allowed (--max-views-per-session " +
                                std::to_string(env_.limits->max_views_per_session) + ")");
    }
  }
  ViewState view;
  view.id = new_view_id();
  view.config = config;
  view.camera = default_camera_;
  view.seq = applying_seq_;
  view.one_off = !counts_against_limit;
  if (camera) {
    DDGI_ASSIGN_OR_RETURN(view.camera, camera_from_proto(*camera, default_camera_));
  }
  if (!view.one_off) env_.metrics->views.fetch_add(1);
  const std::string id = view.id;
  return &views_.emplace(id, std::move(view)).first->second;
}

void Session::erase_view(const std::string& view_id) {
  auto it = views_.find(view_id);
  if (it == views_.end()) return;
  ViewState& view = it->second;
  for (auto& stream : view.streams) stream->finish(grpc::Status::OK);
  for (auto& waiter : view.waiters) waiter(unavailable("view " + view_id + " was deleted"));
  if (!view.one_off) env_.metrics->views.fetch_sub(1);
  views_.erase(it);
}

void Session::fail_view(ViewState& view, const Error& error) {
  for (auto& stream : view.streams) stream->finish(to_grpc(error));
  for (auto& waiter : view.waiters) waiter(error);
  view.streams.clear();
  view.waiters.clear();
}

void Session::fill_view(const ViewState& view, v1::ViewInfo* info) const {
  info->set_view_id(view.id);
  to_proto(view.config, info->mutable_settings());
  to_proto(view.camera, info->mutable_camera());
  info->set_command_seq(view.seq);
}

void Session::create_view(ViewConfig config, std::optional<v1::Camera> camera, v1::ViewInfo* reply,
                          Completion done) {
  enqueue_sync(
      true,
      [this, config, camera, reply]() -> Status {
        DDGI_ASSIGN_OR_RETURN(ViewState * view, add_view(config, camera, true));
        fill_view(*view, reply);
        return ok_status();
      },
      std::move(done));
}

void Session::update_view(std::string view_id, v1::ViewSettings settings, v1::ViewInfo* reply,
                          Completion done) {
  enqueue_sync(
      true,
      [this, view_id, settings, reply]() -> Status {
        DDGI_ASSIGN_OR_RETURN(ViewState * view, find_view(view_id));
        DDGI_TRY(apply_view_settings(settings, *env_.limits, view->config));
        view->seq = applying_seq_;
        fill_view(*view, reply);
        return ok_status();
      },
      std::move(done));
}

void Session::delete_view(std::string view_id, Completion done) {
  enqueue_sync(
      true,
      [this, view_id]() -> Status {
        DDGI_TRY(find_view(view_id));
        erase_view(view_id);
        return ok_status();
      },
      std::move(done));
}

void Session::set_camera(std::string view_id, v1::Camera camera, v1::ViewInfo* reply,
                         Completion done) {
  enqueue_sync(
      true,
      [this, view_id, camera, reply]() -> Status {
        DDGI_ASSIGN_OR_RETURN(ViewState * view, find_view(view_id));
        DDGI_ASSIGN_OR_RETURN(view->camera, camera_from_proto(camera, default_camera_));
        view->seq = applying_seq_;
        fill_view(*view, reply);
        return ok_status();
      },
      std::move(done));
}

// ---- Lights and instances
// -------------------------------------------------------------------------

void Session::fill_light(const LightSlot& slot, v1::LightEntry* entry) const {
  entry->set_light_id(slot.id);
  to_proto(slot.light, entry->mutable_light());
}

Status Session::upload_lights() {
  std::vector<Light> lights;
  for (const LightSlot& slot : lights_) lights.push_back(slot.light);
  return gi_->scene().set_lights(lights);
}

void Session::add_light(v1::Light light, v1::LightReply* reply, Completion done) {
  enqueue_sync(
      true,
      [this, light, reply]() -> Status {
        if (!gi_) return failed_precondition("session " + id_ + " has no scene loaded");
        if (lights_.size() >= env_.limits->max_lights) {
          return resource_exhausted("session " + id_ + " already has " +
                                    std::to_string(lights_.size()) +
                                    " lights, the most allowed (--max-lights " +
                                    std::to_string(env_.limits->max_lights) + ")");
        }
        DDGI_ASSIGN_OR_RETURN(const Light value, light_from_proto(light, Light{}));
        lights_.push_back({next_light_id_, value});
        const Status status = upload_lights();
        if (!status.ok()) {
          lights_.pop_back();
          return status;
        }
        ++next_light_id_;
        fill_light(lights_.back(), reply->mutable_light());
        reply->set_command_seq(applying_seq_);
        return ok_status();
      },
      std::move(done));
}

void Session::update_light(uint32_t light_id, v1::Light light, v1::LightReply* reply,
                           Completion done) {
  enqueue_sync(
      true,
      [this, light_id, light, reply]() -> Status {
        auto it = std::find_if(lights_.begin(), lights_.end(),
                               [&](const LightSlot& slot) { return slot.id == light_id; });
        if (it == lights_.end()) {
          return not_found("session " + id_ + " has no light " + std::to_string(light_id));
        }
        DDGI_ASSIGN_OR_RETURN(const Light value, light_from_proto(light, it->light));
        const Light old = it->light;
        it->light = value;
        const Status status = upload_lights();
        if (!status.ok()) {
          it->light = old;
          return status;
        }
        fill_light(*it, reply->mutable_light());
        reply->set_command_seq(applying_seq_);
        return ok_status();
      },
      std::move(done));
}

void Session::remove_light(uint32_t light_id, v1::LightReply* reply, Completion done) {
  enqueue_sync(
      true,
      [this, light_id, reply]() -> Status {
        auto it = std::find_if(lights_.begin(), lights_.end(),
                               [&](const LightSlot& slot) { return slot.id == light_id; });
        if (it == lights_.end()) {
          return not_found("session " + id_ + " has no light " + std::to_string(light_id));
        }
        const LightSlot removed = *it;
        lights_.erase(it);
        const Status status = upload_lights();
        if (!status.ok()) {
          lights_.push_back(removed);
          std::sort(lights_.begin(), lights_.end(),
                    [](const LightSlot& a, const LightSlot& b) { return a.id < b.id; });
          return status;
        }
        fill_light(removed, reply->mutable_light());
        reply->set_command_seq(applying_seq_);
        return ok_status();
      },
      std::move(done));
}

void Session::set_instance_transform(uint32_t index, glm::mat4 transform, v1::InstanceReply* reply,
                                     Completion done) {
  enqueue_sync(
      true,
      [this, index, transform, reply]() -> Status {
        if (!gi_) return failed_precondition("session " + id_ + " has no scene loaded");
        const auto& instances = gi_->scene().scene().instances;
        if (index >= instances.size()) {
          return not_found("session " + id_ + " has no instance " + std::to_string(index) +
                           " (its scene has " + std::to_string(instances.size()) + " instances)");
        }
        DDGI_TRY(gi_->scene().set_instance_transform(index, transform));
        auto* instance = reply->mutable_instance();
        instance->set_index(index);
        instance->set_name(gi_->scene().scene().instances[index].name);
        to_proto(gi_->scene().scene().instances[index].transform, instance->mutable_transform());
        reply->set_command_seq(applying_seq_);
        return ok_status();
      },
      std::move(done));
}

// ---- Field
// ----------------------------------------------------------------------------------------

namespace {

// Every parameter of `table` with its value in `values`.
template <typename P>
void add_param_values(const ParamTable<P>& table, const P& values, v1::FieldParams* params) {
  for (const ParamSpec<P>& spec : table.specs()) {
    auto* p = params->add_params();
    p->set_name(spec.name);
    p->set_value(spec.format(values));
  }
}

}  // namespace

void Session::fill_field(v1::FieldParams* params) const {
  params->Clear();
  params->set_field(v1::FIELD_KIND_IRRADIANCE);
  add_param_values(field_param_table(), field()->params(), params);
  params->set_probes(probe_count(field()->params()));
  params->set_gpu_bytes(field()->gpu_bytes());
  params->set_updates(field()->updates());
  params->set_command_seq(applying_seq_);
  const ProbeStateCounts counts = field()->probe_counts();
  v1::ProbeStateCounts* states = params->mutable_probe_states();
  states->set_vigilant(counts.vigilant);
  states->set_awake(counts.awake);
  states->set_sleeping(counts.sleeping);
  states->set_off(counts.off);
}

void Session::fill_shadow_field(v1::FieldParams* params) const {
  params->Clear();
  params->set_field(v1::FIELD_KIND_SHADOW);
  add_param_values(shadow_param_table(), shadow_field()->params(), params);
  params->set_probes(probe_count(shadow_field()->params()));
  params->set_gpu_bytes(shadow_field()->gpu_bytes());
  params->set_updates(shadow_field()->updates());
  params->set_command_seq(applying_seq_);
}

Status Session::require_field(v1::FieldKind kind) const {
  if (kind == v1::FIELD_KIND_SHADOW && !shadow_field()) {
    return failed_precondition("session " + id_ +
                               " has no shadow field (create it with direct_mode SHADOW_FIELD "
                               "or AMBIENT_OCCLUSION)");
  }
  if (kind != v1::FIELD_KIND_SHADOW && !field()) {
    return failed_precondition("session " + id_ +
                               " runs without GI (CreateSession gi=false): it has no field");
  }
  return ok_status();
}

void Session::get_field_params(v1::FieldKind kind, v1::FieldParams* reply, Completion done) {
  enqueue_sync(
      false,
      [this, kind, reply]() -> Status {
        DDGI_TRY(require_field(kind));
        if (kind == v1::FIELD_KIND_SHADOW) {
          fill_shadow_field(reply);
        } else {
          fill_field(reply);
        }
        return ok_status();
      },
      std::move(done));
}

void Session::set_field_params(v1::FieldKind kind, std::vector<std::string> assignments,
                               v1::FieldParams* reply, Completion done) {
  enqueue_sync(
      true,
      [this, kind, assignments, reply]() -> Status {
        DDGI_TRY(require_field(kind));
        if (kind == v1::FIELD_KIND_SHADOW) {
          ShadowFieldParams params = shadow_field()->params();
          DDGI_TRY(shadow_param_table().apply(params, assignments));
          DDGI_TRY(shadow_field()->set_params(params));
          fill_shadow_field(reply);
        } else {
          IrradianceFieldParams params = field()->params();
          DDGI_TRY(field_param_table().apply(params, assignments));
          DDGI_TRY(field()->set_params(params));
          fill_field(reply);
        }
        LOG_INFO << "field parameters changed session=" << id_
                 << " field=" << (kind == v1::FIELD_KIND_SHADOW ? "shadow" : "irradiance")
                 << " count=" << assignments.size();
        return ok_status();
      },
      std::move(done));
}

// ---- Frames, queries, atlases
// ---------------------------------------------------------------------

void Session::render_frame(std::string view_id, ViewConfig config, std::optional<v1::Camera> camera,
                           FrameWaiter waiter) {
  auto shared_waiter = std::make_shared<FrameWaiter>(std::move(waiter));
  enqueue(
      false,
      [this, view_id, config, camera, shared_waiter](Completion finish) {
        Result<ViewState*> view =
            view_id.empty() ? add_view(config, camera, false) : find_view(view_id);
        if (!view.ok()) {
          finish(view.error());
          return;
        }
        (*view)->waiters.push_back(std::move(*shared_waiter));
      },
      [shared_waiter](const Status& status) {
        if (!status.ok()) (*shared_waiter)(status.error());
      });
}

void Session::attach_stream(std::string view_id, ViewConfig config,
                            std::optional<v1::Camera> camera,
                            std::shared_ptr<FrameStreamState> stream) {
  enqueue(
      false,
      [this, view_id, config, camera, stream](Completion finish) {
        Result<ViewState*> view =
            view_id.empty() ? add_view(config, camera, true) : find_view(view_id);
        if (!view.ok()) {
          finish(view.error());
          return;
        }
        if (view_id.empty()) (*view)->owned_by_stream = true;
        (*view)->streams.push_back(stream);
        LOG_INFO << "stream attached session=" << id_ << " view=" << (*view)->id;
      },
      [stream](const Status& status) {
        if (!status.ok()) stream->finish(to_grpc(status.error()));
      });
}

void Session::detach_stream(std::shared_ptr<FrameStreamState> stream) {
  enqueue(
      false,
      [this, stream](Completion finish) {
        std::vector<std::string> orphans;
        for (auto& [view_id, view] : views_) {
          const size_t before = view.streams.size();
          std::erase(view.streams, stream);
          if (view.streams.size() != before) {
            LOG_INFO << "stream detached session=" << id_ << " view=" << view_id
                     << " dropped=" << stream->dropped();
          }
          // The frame loop may have dropped the ended stream already; either way a view made
          // for a stream goes with it.
          if (view.owned_by_stream && view.streams.empty()) orphans.push_back(view_id);
        }
        for (const std::string& view_id : orphans) erase_view(view_id);
        finish(ok_status());
      },
      [](const Status&) {});
}

void Session::query(std::vector<IrradianceQuery> points, v1::QueryIrradianceReply* reply,
                    Completion done) {
  auto shared_points = std::make_shared<std::vector<IrradianceQuery>>(std::move(points));
  enqueue_sync(
      false,
      [this, shared_points, reply]() -> Status {
        if (!field()) {
          return failed_precondition("session " + id_ +
                                     " runs without GI (CreateSession gi=false): it has no field");
        }
        DDGI_ASSIGN_OR_RETURN(const std::vector<glm::vec3> values, field()->query(*shared_points));
        for (const glm::vec3& value : values) to_proto(value, reply->add_irradiance());
        reply->set_field_updates(field()->updates());
        return ok_status();
      },
      std::move(done));
}

void Session::dump_atlas(v1::AtlasKind kind, v1::AtlasFormat format, AtlasDone done) {
  auto shared_done = std::make_shared<AtlasDone>(std::move(done));
  enqueue(
      false,
      [this, kind, format, shared_done](Completion) {
        auto result = [&]() -> Result<std::pair<v1::AtlasMetadata, std::vector<uint8_t>>> {
          const bool shadow_kind =
              kind == v1::ATLAS_KIND_SHADOW || kind == v1::ATLAS_KIND_SHADOW_MOMENTS;
          DDGI_TRY(require_field(shadow_kind ? v1::FIELD_KIND_SHADOW : v1::FIELD_KIND_IRRADIANCE));
          DDGI_ASSIGN_OR_RETURN(auto dump,
                                read_atlas(*env_.context, field(), shadow_field(), kind, format));
          DDGI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, encode_atlas(dump.second, dump.first));
          return std::make_pair(std::move(dump.first), std::move(bytes));
        }();
        (*shared_done)(std::move(result));
      },
      [shared_done](const Status& status) {
        if (!status.ok()) (*shared_done)(status.error());
      });
}

}  // namespace ddgi::service
