#include "service/render_service.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

#include "core/log.h"
#include "gi/field_params.h"
#include "gi/shadow_params.h"
#include "rpc/status_code_name.h"
#include "service/chunk_stream.h"
#include "service/frame_stream.h"
#include "service/grpc_status.h"
#include "service/probe_stream.h"
#include "service/session_budget.h"
#include "service/text.h"

#ifndef DDGI_VERSION
#define DDGI_VERSION "dev"
#endif

namespace ddgi::service {
namespace {

Status require_view_id(const std::string& view_id) {
  if (view_id.empty()) return invalid_argument("view_id is empty");
  if (view_id.size() > 64) return invalid_argument("view_id is longer than 64 bytes");
  return ok_status();
}

std::vector<std::string> assignments_of(
    const google::protobuf::RepeatedPtrField<v1::FieldParam>& params) {
  std::vector<std::string> out;
  for (const v1::FieldParam& p : params) out.push_back(p.name() + "=" + p.value());
  return out;
}

// Every parameter of `table` with its help (the range and the reason).
template <typename P>
void describe_params(const ParamTable<P>& table,
                     google::protobuf::RepeatedPtrField<v1::FieldParamInfo>* out) {
  for (const ParamSpec<P>& spec : table.specs()) {
    auto* p = out->Add();
    p->set_name(spec.name);
    p->set_description(spec.help);
  }
}

// Field-parameter requests carry text: bound it before the parser sees it.
Status check_field_params(const google::protobuf::RepeatedPtrField<v1::FieldParam>& params,
                          v1::FieldKind kind) {
  if (!v1::FieldKind_IsValid(kind)) {
    return invalid_argument("field " + std::to_string(int(kind)) + " is not a FieldKind");
  }
  if (params.size() > 256) {
    return invalid_argument("at most 256 field parameters per request (got " +
                            std::to_string(params.size()) + ")");
  }
  for (const v1::FieldParam& p : params) {
    if (p.name().size() > 64 || p.value().size() > 256) {
      return invalid_argument("field parameter " + printable(p.name()) +
                              ": names are at most 64 bytes, values 256");
    }
  }
  // Names and values are checked on default parameters now, so typos fail before any queueing;
  // ranges that depend on the scene's grid are checked again when applied.
  if (kind == v1::FIELD_KIND_SHADOW) {
    ShadowFieldParams scratch;
    return shadow_param_table().apply(scratch, assignments_of(params));
  }
  std::vector<std::string> assignments = assignments_of(params);
  DDGI_TRY(take_budget(assignments));
  IrradianceFieldParams scratch;
  return field_param_table().apply(scratch, assignments);
}

// Loading a library scene fails with messages naming server files: the client gets them
// without absolute paths (SceneLibrary::without_server_paths), the log keeps them whole.
Completion without_server_paths(const SceneLibrary& library, Completion done) {
  return [&library, done = std::move(done)](const Status& status) {
    if (status.ok()) return done(status);
    const Error shown = library.without_server_paths(status.error());
    if (shown.message != status.error().message) {
      LOG_INFO << "scene load failed: " << status.error().message;
    }
    done(shown);
  };
}

}  // namespace

void RenderServiceImpl::refuse_new_work(std::string why) {
  std::lock_guard<std::mutex> lock(refusal_mutex_);
  if (refusal_.empty()) refusal_ = std::move(why);
}

Status RenderServiceImpl::refusal() const {
  std::lock_guard<std::mutex> lock(refusal_mutex_);
  if (refusal_.empty()) return ok_status();
  return unavailable(refusal_);
}

RenderServiceImpl::RenderServiceImpl(vk::Context& context, const ServiceLimits& limits,
                                     SceneLibrary library, BearerAuth auth, Metrics& metrics,
                                     SessionRegistry& sessions)
    : context_(context),
      limits_(limits),
      library_(std::move(library)),
      auth_(std::move(auth)),
      metrics_(metrics),
      sessions_(sessions) {}

RenderServiceImpl::~RenderServiceImpl() {
  // An export's thread touches this object until its last step, the count's decrement; exports
  // take seconds at most, so this wait is short and bounded.
  for (int i = 0; i < 6000 && scene_exports_.load() > 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void RenderServiceImpl::record(const char* method, const std::string& session_id,
                               const grpc::Status& status) {
  metrics_.count_rpc(method, status_code_name(status.error_code()));
  if (status.ok()) {
    LOG_DEBUG << "rpc method=" << method << " session=" << printable(session_id) << " code=OK";
  } else {
    LOG_INFO << "rpc method=" << method << " session=" << printable(session_id)
             << " code=" << status_code_name(status.error_code())
             << " message=" << status.error_message();
  }
}

grpc::ServerUnaryReactor* RenderServiceImpl::finish(grpc::ServerUnaryReactor* reactor,
                                                    const char* method,
                                                    const std::string& session_id,
                                                    const grpc::Status& status) {
  record(method, session_id, status);
  reactor->Finish(status);
  return reactor;
}

Completion RenderServiceImpl::completion(grpc::ServerUnaryReactor* reactor, const char* method,
                                         std::string session_id) {
  return [this, reactor, method, session_id](const Status& status) {
    finish(reactor, method, session_id, to_grpc(status));
  };
}

template <typename Body>
grpc::ServerUnaryReactor* RenderServiceImpl::unary(grpc::CallbackServerContext* context,
                                                   const char* method,
                                                   const std::string& session_id, Body&& body) {
  auto* reactor = context->DefaultReactor();
  if (grpc::Status denied = auth_.check(*context); !denied.ok()) {
    return finish(reactor, method, session_id, denied);
  }
  // An error from `body` finishes the call at once; otherwise `body` handed `done` to a session.
  Completion done = completion(reactor, method, session_id);
  const Status status = body(done);
  if (!status.ok() && done) done(status);
  return reactor;
}

grpc::ServerUnaryReactor* RenderServiceImpl::GetServerInfo(grpc::CallbackServerContext* context,
                                                           const v1::GetServerInfoRequest*,
                                                           v1::ServerInfo* reply) {
  return unary(context, "GetServerInfo", "", [&](Completion& done) -> Status {
    const vk::DeviceCapabilities& caps = context_.caps();
    reply->set_version(DDGI_VERSION);
    reply->set_device_name(caps.device_name);
    reply->set_driver_name(caps.driver_name);
    reply->set_backend(vk::backend_name(context_.default_backend()));
    reply->set_ray_query(caps.ray_query);
    reply->set_ray_tracing_pipeline(caps.ray_tracing_pipeline);
    v1::Limits* limits = reply->mutable_limits();
    limits->set_max_sessions(limits_.max_sessions);
    limits->set_max_views_per_session(limits_.max_views_per_session);
    limits->set_max_width(limits_.max_width);
    limits->set_max_height(limits_.max_height);
    limits->set_max_message_bytes(limits_.max_message_bytes);
    limits->set_max_upload_bytes(limits_.max_upload_bytes);
    limits->set_max_query_points(limits_.max_query_points);
    limits->set_max_lights(limits_.max_lights);
    limits->set_gpu_memory_budget_bytes(context_.memory_budget());
    for (const std::string& name : library_.names()) reply->add_scenes(name);
    reply->set_sessions(static_cast<uint32_t>(sessions_.size()));
    reply->set_gpu_memory_used_bytes(context_.allocated_bytes());
    reply->set_auth_required(auth_.enabled());
    describe_params(field_param_table(), reply->mutable_field_params());
    auto* budget = reply->mutable_field_params()->Add();
    budget->set_name(kBudgetParam);
    budget->set_description(kBudgetParamHelp);
    describe_params(shadow_param_table(), reply->mutable_shadow_field_params());
    done(ok_status());
    return ok_status();
  });
}

Result<SceneRequest> RenderServiceImpl::scene_request(const v1::SceneSource& source,
                                                      uint32_t warmup, bool has_warmup) const {
  SceneRequest request;
  request.warmup_updates = has_warmup ? warmup : 16;
  if (request.warmup_updates > limits_.max_warmup_updates) {
    return invalid_argument("warmup_updates " + std::to_string(warmup) + " is out of range [0, " +
                            std::to_string(limits_.max_warmup_updates) +
                            "] (--max-warmup-updates)");
  }
  switch (source.source_case()) {
    case v1::SceneSource::kName: {
      DDGI_ASSIGN_OR_RETURN(request.path, library_.resolve(source.name()));
      request.label = source.name();
      break;
    }
    case v1::SceneSource::kGlb: {
      const std::string& glb = source.glb();
      if (glb.empty()) return invalid_argument("scene.glb is empty");
      if (glb.size() > limits_.max_upload_bytes) {
        return resource_exhausted(
            "the uploaded .glb has " + std::to_string(glb.size()) + " bytes, more than the " +
            std::to_string(limits_.max_upload_bytes) + "-byte upload limit (--max-upload-bytes)");
      }
      request.upload.assign(glb.begin(), glb.end());
      request.label = "upload:" + std::to_string(glb.size());
      break;
    }
    default:
      return invalid_argument("scene: give a library name (scene.name) or .glb bytes (scene.glb)");
  }
  return request;
}

grpc::ServerUnaryReactor* RenderServiceImpl::CreateSession(grpc::CallbackServerContext* context,
                                                           const v1::CreateSessionRequest* request,
                                                           v1::SessionInfo* reply) {
  return unary(context, "CreateSession", "", [&](Completion& done) -> Status {
    if (request->scene().has_name()) done = without_server_paths(library_, std::move(done));
    DDGI_TRY(refusal());
    DDGI_ASSIGN_OR_RETURN(
        SceneRequest scene,
        scene_request(request->scene(), request->warmup_updates(), request->has_warmup_updates()));
    SessionOptions options;
    options.gi = !request->has_gi() || request->gi();
    DDGI_ASSIGN_OR_RETURN(options.direct_mode, direct_mode_from_proto(request->direct_mode()));
    DDGI_TRY(check_field_params(request->field_params(), v1::FIELD_KIND_IRRADIANCE));
    options.field_assignments = assignments_of(request->field_params());
    DDGI_ASSIGN_OR_RETURN(options.budget_ms, take_budget(options.field_assignments));
    if (!request->shadow_field_params().empty() && !uses_shadow_field(options.direct_mode)) {
      return invalid_argument(
          "shadow_field_params need direct_mode SHADOW_FIELD or AMBIENT_OCCLUSION (a session "
          "has a shadow field only in those modes)");
    }
    DDGI_TRY(check_field_params(request->shadow_field_params(), v1::FIELD_KIND_SHADOW));
    options.shadow_assignments = assignments_of(request->shadow_field_params());
    // A client gone (cancelled, or past its deadline) before its session is ready never learns
    // the id: close the session rather than leave it holding a slot and GPU memory.
    Completion reply_or_close = [this, context, reply, done](const Status& status) {
      if (!status.ok() || !context->IsCancelled()) {
        done(status);
        return;
      }
      const std::string id = reply->session_id();
      LOG_INFO << "session abandoned session=" << id
               << ": its client went away before it was ready; closing it";
      (void)sessions_.close(id, nullptr);
      done(unavailable("the client went away (cancelled, or past its deadline) before session " +
                       id + " was ready; the session was closed"));
    };
    DDGI_TRY(sessions_.create(std::move(options), std::move(scene), reply, reply_or_close));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::LoadScene(grpc::CallbackServerContext* context,
                                                       const v1::LoadSceneRequest* request,
                                                       v1::SessionInfo* reply) {
  return unary(context, "LoadScene", request->session_id(), [&](Completion& done) -> Status {
    if (request->scene().has_name()) done = without_server_paths(library_, std::move(done));
    DDGI_ASSIGN_OR_RETURN(
        SceneRequest scene,
        scene_request(request->scene(), request->warmup_updates(), request->has_warmup_updates()));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->load_scene(std::move(scene), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::CloseSession(grpc::CallbackServerContext* context,
                                                          const v1::CloseSessionRequest* request,
                                                          v1::CloseSessionReply*) {
  return unary(context, "CloseSession", request->session_id(), [&](Completion& done) -> Status {
    // The reply waits until the session's GPU memory is freed.
    auto shared_done = std::make_shared<Completion>(done);  // a copy: on error `done` answers
    DDGI_TRY(
        sessions_.close(request->session_id(), [shared_done] { (*shared_done)(ok_status()); }));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::ListSessions(grpc::CallbackServerContext* context,
                                                          const v1::ListSessionsRequest*,
                                                          v1::ListSessionsReply* reply) {
  return unary(context, "ListSessions", "", [&](Completion& done) -> Status {
    for (v1::SessionSummary& summary : sessions_.list()) {
      *reply->add_sessions() = std::move(summary);
    }
    done(ok_status());
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::GetSession(grpc::CallbackServerContext* context,
                                                        const v1::GetSessionRequest* request,
                                                        v1::SessionInfo* reply) {
  return unary(context, "GetSession", request->session_id(), [&](Completion& done) -> Status {
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->get_info(reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::CreateView(grpc::CallbackServerContext* context,
                                                        const v1::CreateViewRequest* request,
                                                        v1::ViewInfo* reply) {
  return unary(context, "CreateView", request->session_id(), [&](Completion& done) -> Status {
    ViewConfig config;
    DDGI_TRY(apply_view_settings(request->settings(), limits_, config));
    std::optional<v1::Camera> camera;
    if (request->has_camera()) {
      DDGI_TRY(camera_from_proto(request->camera(), Camera{}));
      camera = request->camera();
    }
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->create_view(config, std::move(camera), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::UpdateView(grpc::CallbackServerContext* context,
                                                        const v1::UpdateViewRequest* request,
                                                        v1::ViewInfo* reply) {
  return unary(context, "UpdateView", request->session_id(), [&](Completion& done) -> Status {
    DDGI_TRY(require_view_id(request->view_id()));
    ViewConfig scratch;
    DDGI_TRY(apply_view_settings(request->settings(), limits_, scratch));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->update_view(request->view_id(), request->settings(), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::DeleteView(grpc::CallbackServerContext* context,
                                                        const v1::DeleteViewRequest* request,
                                                        v1::DeleteViewReply*) {
  return unary(context, "DeleteView", request->session_id(), [&](Completion& done) -> Status {
    DDGI_TRY(require_view_id(request->view_id()));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->delete_view(request->view_id(), std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::SetCamera(grpc::CallbackServerContext* context,
                                                       const v1::SetCameraRequest* request,
                                                       v1::ViewInfo* reply) {
  return unary(context, "SetCamera", request->session_id(), [&](Completion& done) -> Status {
    DDGI_TRY(require_view_id(request->view_id()));
    DDGI_TRY(camera_from_proto(request->camera(), Camera{}));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->set_camera(request->view_id(), request->camera(), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::AddLight(grpc::CallbackServerContext* context,
                                                      const v1::AddLightRequest* request,
                                                      v1::LightReply* reply) {
  return unary(context, "AddLight", request->session_id(), [&](Completion& done) -> Status {
    DDGI_TRY(light_from_proto(request->light(), Light{}));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->add_light(request->light(), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::UpdateLight(grpc::CallbackServerContext* context,
                                                         const v1::UpdateLightRequest* request,
                                                         v1::LightReply* reply) {
  return unary(context, "UpdateLight", request->session_id(), [&](Completion& done) -> Status {
    // Values are checked on their own here; against the light's other values when applied.
    Light scratch;
    scratch.inner_cone_angle = 0.0f;
    scratch.outer_cone_angle = 1.5707964f;
    DDGI_TRY(light_from_proto(request->light(), scratch));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->update_light(request->light_id(), request->light(), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::RemoveLight(grpc::CallbackServerContext* context,
                                                         const v1::RemoveLightRequest* request,
                                                         v1::LightReply* reply) {
  return unary(context, "RemoveLight", request->session_id(), [&](Completion& done) -> Status {
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->remove_light(request->light_id(), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::SetInstanceTransform(
    grpc::CallbackServerContext* context, const v1::SetInstanceTransformRequest* request,
    v1::InstanceReply* reply) {
  return unary(
      context, "SetInstanceTransform", request->session_id(), [&](Completion& done) -> Status {
        DDGI_ASSIGN_OR_RETURN(const glm::mat4 transform, matrix_from_proto(request->transform()));
        DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
        session->set_instance_transform(request->instance_index(), transform, reply,
                                        std::move(done));
        return ok_status();
      });
}

grpc::ServerUnaryReactor* RenderServiceImpl::GetFieldParams(
    grpc::CallbackServerContext* context, const v1::GetFieldParamsRequest* request,
    v1::FieldParams* reply) {
  return unary(context, "GetFieldParams", request->session_id(), [&](Completion& done) -> Status {
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    if (!v1::FieldKind_IsValid(request->field())) {
      return invalid_argument("field " + std::to_string(int(request->field())) +
                              " is not a FieldKind");
    }
    session->get_field_params(request->field(), reply, std::move(done));
    return ok_status();
  });
}

grpc::ServerUnaryReactor* RenderServiceImpl::SetFieldParams(
    grpc::CallbackServerContext* context, const v1::SetFieldParamsRequest* request,
    v1::FieldParams* reply) {
  return unary(context, "SetFieldParams", request->session_id(), [&](Completion& done) -> Status {
    if (request->params().empty()) return invalid_argument("params is empty: nothing to set");
    DDGI_TRY(check_field_params(request->params(), request->field()));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    session->set_field_params(request->field(), assignments_of(request->params()), reply,
                              std::move(done));
    return ok_status();
  });
}

Status RenderServiceImpl::check_view_request(const std::string& view_id,
                                             const v1::ViewSettings& settings,
                                             const v1::Camera* camera, ViewConfig* config) const {
  if (!view_id.empty()) {
    DDGI_TRY(require_view_id(view_id));
    if (camera != nullptr || settings.ByteSizeLong() != 0) {
      return invalid_argument(
          "give either view_id (an existing view) or settings/camera (a new view), not both");
    }
    return ok_status();
  }
  DDGI_TRY(apply_view_settings(settings, limits_, *config));
  if (camera != nullptr) DDGI_TRY(camera_from_proto(*camera, Camera{}));
  return ok_status();
}

grpc::ServerUnaryReactor* RenderServiceImpl::RenderFrame(grpc::CallbackServerContext* context,
                                                         const v1::RenderFrameRequest* request,
                                                         v1::Frame* reply) {
  return unary(context, "RenderFrame", request->session_id(), [&](Completion& done) -> Status {
    ViewConfig config;
    DDGI_TRY(check_view_request(request->view_id(), request->settings(),
                                request->has_camera() ? &request->camera() : nullptr, &config));
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    std::optional<v1::Camera> camera;
    if (request->has_camera()) camera = request->camera();
    auto shared_done = std::make_shared<Completion>(std::move(done));
    session->render_frame(request->view_id(), config, std::move(camera),
                          [reply, shared_done](Result<std::shared_ptr<const v1::Frame>> frame) {
                            if (frame.ok()) *reply = **frame;
                            (*shared_done)(frame.ok() ? ok_status() : Status(frame.error()));
                          });
    return ok_status();
  });
}

grpc::ServerWriteReactor<v1::Frame>* RenderServiceImpl::StreamFrames(
    grpc::CallbackServerContext* context, const v1::StreamFramesRequest* request) {
  const double max_fps = request->max_fps();
  auto* reactor =
      new FrameStreamReactor(metrics_, std::isfinite(max_fps) && max_fps > 0.0 ? max_fps : 0.0);
  std::shared_ptr<FrameStreamState> state = reactor->state();
  const std::string session_id = request->session_id();
  auto fail = [&](const grpc::Status& status) {
    record("StreamFrames", session_id, status);
    state->finish(status);
    return reactor;
  };
  if (grpc::Status denied = auth_.check(*context); !denied.ok()) return fail(denied);
  if (Status refused = refusal(); !refused.ok()) return fail(to_grpc(refused.error()));
  if (!std::isfinite(max_fps) || max_fps < 0.0 || max_fps > 1000.0) {
    return fail(to_grpc(invalid_argument("max_fps must be finite and in [0, 1000] (got " +
                                         std::to_string(max_fps) + ")")));
  }
  ViewConfig config;
  const Status valid =
      check_view_request(request->view_id(), request->settings(),
                         request->has_camera() ? &request->camera() : nullptr, &config);
  if (!valid.ok()) return fail(to_grpc(valid));
  auto session = sessions_.find(session_id);
  if (!session.ok()) return fail(to_grpc(session.error()));
  std::optional<v1::Camera> camera;
  if (request->has_camera()) camera = request->camera();
  std::weak_ptr<Session> weak = *session;
  reactor->set_on_done([this, weak, state, session_id] {
    record("StreamFrames", session_id, grpc::Status::OK);
    if (auto live = weak.lock()) live->detach_stream(state);
  });
  (*session)->attach_stream(request->view_id(), config, std::move(camera), state);
  return reactor;
}

grpc::ServerWriteReactor<v1::ProbeUpdate>* RenderServiceImpl::StreamProbes(
    grpc::CallbackServerContext* context, const v1::StreamProbesRequest* request) {
  ProbeStreamOptions options;
  if (request->change_threshold() != 0.0f) options.change_threshold = request->change_threshold();
  if (request->full_refresh_interval() != 0) {
    options.full_refresh_interval = request->full_refresh_interval();
  }
  auto* reactor = new ProbeStreamReactor(options);
  std::shared_ptr<ProbeStreamState> state = reactor->state();
  const std::string session_id = request->session_id();
  auto fail = [&](const grpc::Status& status) {
    record("StreamProbes", session_id, status);
    state->finish(status);
    return reactor;
  };
  if (grpc::Status denied = auth_.check(*context); !denied.ok()) return fail(denied);
  if (Status refused = refusal(); !refused.ok()) return fail(to_grpc(refused.error()));
  const float threshold = request->change_threshold();
  if (!std::isfinite(threshold) || threshold < 0.0f || threshold > 1.0f) {
    return fail(to_grpc(invalid_argument("change_threshold must be finite and in [0, 1] (got " +
                                         std::to_string(threshold) + ")")));
  }
  if (request->full_refresh_interval() > 100000) {
    return fail(to_grpc(invalid_argument("full_refresh_interval must be in [0, 100000] (got " +
                                         std::to_string(request->full_refresh_interval()) + ")")));
  }
  auto session = sessions_.find(session_id);
  if (!session.ok()) return fail(to_grpc(session.error()));
  std::weak_ptr<Session> weak = *session;
  reactor->set_on_done([this, weak, state, session_id] {
    record("StreamProbes", session_id, grpc::Status::OK);
    if (auto live = weak.lock()) live->detach_probe_stream(state);
  });
  (*session)->attach_probe_stream(state);
  return reactor;
}

grpc::ServerWriteReactor<v1::AtlasChunk>* RenderServiceImpl::DumpAtlas(
    grpc::CallbackServerContext* context, const v1::DumpAtlasRequest* request) {
  auto* reactor = new AtlasStreamReactor(chunk_bytes());
  auto state = reactor->state();
  const std::string session_id = request->session_id();
  auto fail = [&](const grpc::Status& status) {
    record("DumpAtlas", session_id, status);
    state->finish(status);
    return reactor;
  };
  if (grpc::Status denied = auth_.check(*context); !denied.ok()) return fail(denied);
  v1::AtlasKind kind = request->kind();
  if (!v1::AtlasKind_IsValid(kind) || kind == v1::ATLAS_KIND_UNSPECIFIED) {
    return fail(to_grpc(invalid_argument(
        "kind must be IRRADIANCE, DISTANCE, SHADOW, SHADOW_MOMENTS, PROBE_STATES or SH (got " +
        std::to_string(int(kind)) + ")")));
  }
  v1::AtlasFormat format = request->format();
  if (!v1::AtlasFormat_IsValid(format)) {
    return fail(to_grpc(invalid_argument("format must be EXR or RAW_F32 (got " +
                                         std::to_string(int(format)) + ")")));
  }
  if (format == v1::ATLAS_FORMAT_UNSPECIFIED) format = v1::ATLAS_FORMAT_EXR;
  auto session = sessions_.find(session_id);
  if (!session.ok()) return fail(to_grpc(session.error()));
  const AtlasRequest atlas{kind, format, request->volume()};
  (*session)->dump_atlas(atlas, [this, state, session_id](auto dump) {
    record("DumpAtlas", session_id, dump.ok() ? grpc::Status::OK : to_grpc(dump.error()));
    state->deliver(std::move(dump));
  });
  return reactor;
}

grpc::ServerWriteReactor<v1::SceneChunk>* RenderServiceImpl::ExportScene(
    grpc::CallbackServerContext* context, const v1::ExportSceneRequest* request) {
  auto* reactor = new SceneStreamReactor(chunk_bytes());
  auto state = reactor->state();
  const std::string session_id = request->session_id();
  auto fail = [&](const grpc::Status& status) {
    record("ExportScene", session_id, status);
    state->finish(status);
    return reactor;
  };
  if (grpc::Status denied = auth_.check(*context); !denied.ok()) return fail(denied);
  auto session = sessions_.find(session_id);
  if (!session.ok()) return fail(to_grpc(session.error()));
  // Each export holds a copy of its scene while it is written: a few at a time, server-wide.
  if (scene_exports_.fetch_add(1) >= kMaxSceneExports) {
    --scene_exports_;
    return fail(to_grpc(resource_exhausted(
        std::to_string(kMaxSceneExports) +
        " scene exports are being written (the server's limit); try again shortly")));
  }
  (*session)->export_scene([this, state, session_id](auto exported) {
    record("ExportScene", session_id, exported.ok() ? grpc::Status::OK : to_grpc(exported.error()));
    state->deliver(std::move(exported));
    --scene_exports_;  // last: the destructor waits for this
  });
  return reactor;
}

grpc::ServerUnaryReactor* RenderServiceImpl::QueryIrradiance(
    grpc::CallbackServerContext* context, const v1::QueryIrradianceRequest* request,
    v1::QueryIrradianceReply* reply) {
  return unary(context, "QueryIrradiance", request->session_id(), [&](Completion& done) -> Status {
    const int count = request->points_size();
    if (count < 1 || uint32_t(count) > limits_.max_query_points) {
      return invalid_argument("points has " + std::to_string(count) + " entries; 1 to " +
                              std::to_string(limits_.max_query_points) +
                              " are allowed (--max-query-points)");
    }
    std::vector<IrradianceQuery> points;
    points.reserve(size_t(count));
    for (int i = 0; i < count; ++i) {
      DDGI_ASSIGN_OR_RETURN(IrradianceQuery point, query_from_proto(request->points(i), size_t(i)));
      points.push_back(point);
    }
    DDGI_ASSIGN_OR_RETURN(auto session, sessions_.find(request->session_id()));
    const std::optional<uint32_t> volume =
        request->has_volume() ? std::optional<uint32_t>(request->volume()) : std::nullopt;
    session->query(std::move(points), volume, reply, std::move(done));
    return ok_status();
  });
}

}  // namespace ddgi::service
