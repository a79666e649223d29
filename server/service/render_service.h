// The RenderService RPCs (proto/ddgi/v1/render_service.proto) on gRPC's callback API. Each
// handler checks auth, validates the request (convert.h), finds the session and queues the work
// there; the reply is sent by the session when the command has been applied. No handler waits.
#pragma once

#include <atomic>
#include <mutex>
#include <string>

#include "ddgi/v1/render_service.grpc.pb.h"
#include "service/auth.h"
#include "service/limits.h"
#include "service/metrics.h"
#include "service/scene_library.h"
#include "service/session_registry.h"
#include "vk/context.h"

namespace ddgi::service {

class RenderServiceImpl final : public v1::RenderService::CallbackService {
 public:
  RenderServiceImpl(vk::Context& context, const ServiceLimits& limits, SceneLibrary library,
                    BearerAuth auth, Metrics& metrics, SessionRegistry& sessions);
  // Waits for scene exports still being written (their threads report back here).
  ~RenderServiceImpl() override;

  // New sessions and streams are refused (UNAVAILABLE, with `why`) from now on: the server is
  // shutting down, or its GPU device was lost.
  void refuse_new_work(std::string why);

  grpc::ServerUnaryReactor* GetServerInfo(grpc::CallbackServerContext* context,
                                          const v1::GetServerInfoRequest* request,
                                          v1::ServerInfo* reply) override;
  grpc::ServerUnaryReactor* CreateSession(grpc::CallbackServerContext* context,
                                          const v1::CreateSessionRequest* request,
                                          v1::SessionInfo* reply) override;
  grpc::ServerUnaryReactor* LoadScene(grpc::CallbackServerContext* context,
                                      const v1::LoadSceneRequest* request,
                                      v1::SessionInfo* reply) override;
  grpc::ServerUnaryReactor* CloseSession(grpc::CallbackServerContext* context,
                                         const v1::CloseSessionRequest* request,
                                         v1::CloseSessionReply* reply) override;
  grpc::ServerUnaryReactor* ListSessions(grpc::CallbackServerContext* context,
                                         const v1::ListSessionsRequest* request,
                                         v1::ListSessionsReply* reply) override;
  grpc::ServerUnaryReactor* GetSession(grpc::CallbackServerContext* context,
                                       const v1::GetSessionRequest* request,
                                       v1::SessionInfo* reply) override;
  grpc::ServerUnaryReactor* CreateView(grpc::CallbackServerContext* context,
                                       const v1::CreateViewRequest* request,
                                       v1::ViewInfo* reply) override;
  grpc::ServerUnaryReactor* UpdateView(grpc::CallbackServerContext* context,
                                       const v1::UpdateViewRequest* request,
                                       v1::ViewInfo* reply) override;
  grpc::ServerUnaryReactor* DeleteView(grpc::CallbackServerContext* context,
                                       const v1::DeleteViewRequest* request,
                                       v1::DeleteViewReply* reply) override;
  grpc::ServerUnaryReactor* SetCamera(grpc::CallbackServerContext* context,
                                      const v1::SetCameraRequest* request,
                                      v1::ViewInfo* reply) override;
  grpc::ServerUnaryReactor* AddLight(grpc::CallbackServerContext* context,
                                     const v1::AddLightRequest* request,
                                     v1::LightReply* reply) override;
  grpc::ServerUnaryReactor* UpdateLight(grpc::CallbackServerContext* context,
                                        const v1::UpdateLightRequest* request,
                                        v1::LightReply* reply) override;
  grpc::ServerUnaryReactor* RemoveLight(grpc::CallbackServerContext* context,
                                        const v1::RemoveLightRequest* request,
                                        v1::LightReply* reply) override;
  grpc::ServerUnaryReactor* SetInstanceTransform(grpc::CallbackServerContext* context,
                                                 const v1::SetInstanceTransformRequest* request,
                                                 v1::InstanceReply* reply) override;
  grpc::ServerUnaryReactor* GetFieldParams(grpc::CallbackServerContext* context,
                                           const v1::GetFieldParamsRequest* request,
                                           v1::FieldParams* reply) override;
  grpc::ServerUnaryReactor* SetFieldParams(grpc::CallbackServerContext* context,
                                           const v1::SetFieldParamsRequest* request,
                                           v1::FieldParams* reply) override;
  grpc::ServerUnaryReactor* RenderFrame(grpc::CallbackServerContext* context,
                                        const v1::RenderFrameRequest* request,
                                        v1::Frame* reply) override;
  grpc::ServerWriteReactor<v1::ProbeUpdate>* StreamProbes(
      grpc::CallbackServerContext* context, const v1::StreamProbesRequest* request) override;
  grpc::ServerWriteReactor<v1::Frame>* StreamFrames(
      grpc::CallbackServerContext* context, const v1::StreamFramesRequest* request) override;
  grpc::ServerWriteReactor<v1::AtlasChunk>* DumpAtlas(grpc::CallbackServerContext* context,
                                                      const v1::DumpAtlasRequest* request) override;
  grpc::ServerWriteReactor<v1::SceneChunk>* ExportScene(
      grpc::CallbackServerContext* context, const v1::ExportSceneRequest* request) override;
  grpc::ServerUnaryReactor* QueryIrradiance(grpc::CallbackServerContext* context,
                                            const v1::QueryIrradianceRequest* request,
                                            v1::QueryIrradianceReply* reply) override;

 private:
  template <typename Body>
  grpc::ServerUnaryReactor* unary(grpc::CallbackServerContext* context, const char* method,
                                  const std::string& session_id, Body&& body);
  // Finishes a unary call now, counting and logging it.
  grpc::ServerUnaryReactor* finish(grpc::ServerUnaryReactor* reactor, const char* method,
                                   const std::string& session_id, const grpc::Status& status);
  // The completion a session calls later for a unary call.
  Completion completion(grpc::ServerUnaryReactor* reactor, const char* method,
                        std::string session_id);
  void record(const char* method, const std::string& session_id, const grpc::Status& status);
  // Download chunks (DumpAtlas, ExportScene) leave room for their own fields in the limit.
  size_t chunk_bytes() const {
    return static_cast<size_t>(std::min<uint64_t>(1ull << 20, limits_.max_message_bytes - 4096));
  }
  Result<SceneRequest> scene_request(const v1::SceneSource& source, uint32_t warmup,
                                     bool has_warmup) const;
  // The frame settings of a RenderFrame / StreamFrames request (no view id, or no settings).
  Status check_view_request(const std::string& view_id, const v1::ViewSettings& settings,
                            const v1::Camera* camera, ViewConfig* config) const;

  vk::Context& context_;
  const ServiceLimits limits_;
  const SceneLibrary library_;
  const BearerAuth auth_;
  Metrics& metrics_;
  SessionRegistry& sessions_;
  // Why new sessions and streams are refused; empty while they are not.
  Status refusal() const;
  mutable std::mutex refusal_mutex_;
  std::string refusal_;
  // ExportScene calls whose file is being written (each holds a copy of its scene).
  static constexpr int kMaxSceneExports = 2;
  std::atomic<int> scene_exports_{0};
};

}  // namespace ddgi::service
