// libFuzzer target for the RPC request path (issue 18): arbitrary bytes become one RPC's request
// message (request_input.h says how), sent through an in-process channel (no socket) to a real
// server on lavapipe with auth on, small limits and one live session with a view. Every request
// goes through gRPC's parsing, the auth check, validation, and the session's dispatch and GPU
// work, as from a client. A request must be answered with a status that names a client error
// or a refusal; INTERNAL, UNKNOWN or a missed deadline (a hang), a Vulkan validation message,
// or a sanitizer report is a crash.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "ddgi/v1/render_service.grpc.pb.h"
#include "service/server.h"
#include "tests/fuzz/request_input.h"
#include "vk/context.h"

namespace ddgi::fuzz {
namespace {

using Stub = v1::RenderService::Stub;
constexpr char kToken[] = "fuzz-token";
constexpr int kDeadlineSeconds = 30;  // generous on lavapipe: a scene load with warm-up
// A stream is read for this long at most: one paced by a tiny max_fps sends its first frame and
// then rightly waits, so its deadline passing is no hang (unary calls still have kDeadline).
constexpr int kStreamSeconds = 3;

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "fuzz_requests: %s\n", message.c_str());
  std::abort();
}

// Small limits: every limit is reachable, and no input can make one call slow.
service::ServerOptions fuzz_server_options() {
  service::ServerOptions options;
  options.listen = "127.0.0.1:0";
  options.scene_root = DDGI_TEST_SCENE_ROOT;
  options.auth_token = kToken;
  options.limits.max_sessions = 3;
  options.limits.max_views_per_session = 4;
  options.limits.max_width = 96;
  options.limits.max_height = 96;
  options.limits.max_message_bytes = 1 << 20;
  options.limits.max_upload_bytes = 64 << 10;
  options.limits.max_query_points = 64;
  options.limits.max_lights = 8;
  options.limits.max_warmup_updates = 2;
  options.limits.max_fps = 120;
  options.limits.gpu_memory_budget_bytes = 96ull << 20;
  options.shutdown_grace = std::chrono::milliseconds(3000);
  return options;
}

class Harness {
 public:
  Harness() {
    vk::ContextOptions vulkan;
    vulkan.validation = true;
    vulkan.memory_budget_bytes = 96ull << 20;
    auto context = vk::Context::create(vulkan);
    if (!context.ok()) fail("no Vulkan context: " + context.error().message);
    context_ = std::move(context).value();
    auto server = service::Server::start(*context_, fuzz_server_options());
    if (!server.ok()) fail("the server did not start: " + server.error().message);
    server_ = std::move(server).value();
    stub_ = v1::RenderService::NewStub(server_->in_process_channel());
  }

  Stub& stub() { return *stub_; }
  const std::string& session_id() const { return session_id_; }
  const std::string& view_id() const { return view_id_; }

  std::unique_ptr<grpc::ClientContext> call_context(bool with_token,
                                                    int deadline_seconds = kDeadlineSeconds) const {
    auto context = std::make_unique<grpc::ClientContext>();
    context->set_deadline(std::chrono::system_clock::now() +
                          std::chrono::seconds(deadline_seconds));
    if (with_token) context->AddMetadata("authorization", std::string("Bearer ") + kToken);
    return context;
  }

  // Before each input: the live session and its view exist (an input may have closed or
  // deleted them), and no other session is left (inputs create them).
  void prepare() {
    close_other_sessions();
    v1::GetSessionRequest get;
    get.set_session_id(session_id_);
    v1::SessionInfo info;
    const bool live =
        !session_id_.empty() && stub_->GetSession(call_context(true).get(), get, &info).ok();
    if (!live) create_session();
    v1::UpdateViewRequest probe;  // no settings: changes nothing, says whether the view exists
    probe.set_session_id(session_id_);
    probe.set_view_id(view_id_);
    v1::ViewInfo view;
    if (view_id_.empty() || !stub_->UpdateView(call_context(true).get(), probe, &view).ok()) {
      create_view();
    }
  }

  // After each input: no validation message, the server still answers.
  void check() {
    if (context_->validation_message_count() != 0) fail("Vulkan validation reported a problem");
    v1::GetServerInfoRequest request;
    v1::ServerInfo info;
    const grpc::Status status = stub_->GetServerInfo(call_context(true).get(), request, &info);
    if (!status.ok()) fail("the server stopped answering: " + status.error_message());
  }

 private:
  void create_session() {
    v1::CreateSessionRequest request;
    request.mutable_scene()->set_name("cornell_box");
    request.set_warmup_updates(1);
    for (const auto& [name, value] :
         {std::pair{"counts", "2,2,2"}, {"rays_per_probe", "16"}, {"fixed_rays", "8"}}) {
      v1::FieldParam* param = request.add_field_params();
      param->set_name(name);
      param->set_value(value);
    }
    v1::SessionInfo info;
    const grpc::Status status = stub_->CreateSession(call_context(true).get(), request, &info);
    if (!status.ok()) fail("cannot create the live session: " + status.error_message());
    session_id_ = info.session_id();
  }

  void create_view() {
    v1::CreateViewRequest request;
    request.set_session_id(session_id_);
    request.mutable_settings()->set_width(32);
    request.mutable_settings()->set_height(24);
    v1::ViewInfo info;
    const grpc::Status status = stub_->CreateView(call_context(true).get(), request, &info);
    if (!status.ok()) fail("cannot create the live view: " + status.error_message());
    view_id_ = info.view_id();
  }

  void close_other_sessions() {
    v1::ListSessionsRequest list;
    v1::ListSessionsReply sessions;
    if (!stub_->ListSessions(call_context(true).get(), list, &sessions).ok()) return;
    for (const v1::SessionSummary& summary : sessions.sessions()) {
      if (summary.session_id() == session_id_) continue;
      v1::CloseSessionRequest close;
      close.set_session_id(summary.session_id());
      v1::CloseSessionReply reply;
      (void)stub_->CloseSession(call_context(true).get(), close, &reply);
    }
  }

  std::unique_ptr<vk::Context> context_;
  std::unique_ptr<service::Server> server_;
  std::unique_ptr<Stub> stub_;
  std::string session_id_;
  std::string view_id_;
};

Harness* g_harness = nullptr;

// The live ids replace the message's where the flags ask for them.
void patch_ids(google::protobuf::Message& request, uint8_t flags) {
  const auto set = [&](const char* name, const std::string& value) {
    const google::protobuf::FieldDescriptor* field = request.GetDescriptor()->FindFieldByName(name);
    if (field && !field->is_repeated() &&
        field->type() == google::protobuf::FieldDescriptor::TYPE_STRING) {
      request.GetReflection()->SetString(&request, field, value);
    }
  };
  if (flags & kLiveSession) set("session_id", g_harness->session_id());
  if (flags & kLiveView) set("view_id", g_harness->view_id());
}

// Statuses a request may get: the client's mistake, a refusal, or a stream we cancelled or
// stopped reading (`stream`: its deadline is ours, kStreamSeconds).
void check_status(std::string_view method, const grpc::Status& status, bool stream = false) {
  if (stream && status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED) return;
  switch (status.error_code()) {
    case grpc::StatusCode::INTERNAL:
    case grpc::StatusCode::UNKNOWN:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::UNIMPLEMENTED:
    case grpc::StatusCode::DATA_LOSS:
      fail(std::string(method) + " answered " + std::to_string(int(status.error_code())) + ": " +
           status.error_message());
    default:
      return;
  }
}

template <typename Request, typename Reply>
using UnaryCall = grpc::Status (Stub::*)(grpc::ClientContext*, const Request&, Reply*);
template <typename Request, typename Item>
using StreamCall = std::unique_ptr<grpc::ClientReader<Item>> (Stub::*)(grpc::ClientContext*,
                                                                       const Request&);

template <typename Request, typename Reply>
void unary(UnaryCall<Request, Reply> call, std::string_view method, const uint8_t* data,
           size_t size, uint8_t flags) {
  Request request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return;  // gRPC refuses it first
  patch_ids(request, flags);
  Reply reply;
  auto context = g_harness->call_context(!(flags & kNoToken));
  check_status(method, (g_harness->stub().*call)(context.get(), request, &reply));
}

// Reads at most two messages, then cancels: enough to see a stream start and carry data.
template <typename Request, typename Item>
void stream(StreamCall<Request, Item> call, std::string_view method, const uint8_t* data,
            size_t size, uint8_t flags) {
  Request request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return;
  patch_ids(request, flags);
  auto context = g_harness->call_context(!(flags & kNoToken), kStreamSeconds);
  std::unique_ptr<grpc::ClientReader<Item>> reader =
      (g_harness->stub().*call)(context.get(), request);
  Item item;
  for (int read = 0; read < 2 && reader->Read(&item); ++read) {
  }
  context->TryCancel();
  while (reader->Read(&item)) {
  }
  check_status(method, reader->Finish(), true);
}

void dispatch(size_t method, const uint8_t* data, size_t size, uint8_t flags) {
  const std::string_view name = kMethods[method];
  switch (method) {
    case 0:
      return unary(&Stub::GetServerInfo, name, data, size, flags);
    case 1:
      return unary(&Stub::CreateSession, name, data, size, flags);
    case 2:
      return unary(&Stub::LoadScene, name, data, size, flags);
    case 3:
      return unary(&Stub::CloseSession, name, data, size, flags);
    case 4:
      return unary(&Stub::ListSessions, name, data, size, flags);
    case 5:
      return unary(&Stub::GetSession, name, data, size, flags);
    case 6:
      return unary(&Stub::CreateView, name, data, size, flags);
    case 7:
      return unary(&Stub::UpdateView, name, data, size, flags);
    case 8:
      return unary(&Stub::DeleteView, name, data, size, flags);
    case 9:
      return unary(&Stub::SetCamera, name, data, size, flags);
    case 10:
      return unary(&Stub::AddLight, name, data, size, flags);
    case 11:
      return unary(&Stub::UpdateLight, name, data, size, flags);
    case 12:
      return unary(&Stub::RemoveLight, name, data, size, flags);
    case 13:
      return unary(&Stub::SetInstanceTransform, name, data, size, flags);
    case 14:
      return unary(&Stub::GetFieldParams, name, data, size, flags);
    case 15:
      return unary(&Stub::SetFieldParams, name, data, size, flags);
    case 16:
      return unary(&Stub::RenderFrame, name, data, size, flags);
    case 17:
      return stream(&Stub::StreamFrames, name, data, size, flags);
    case 18:
      return stream(&Stub::DumpAtlas, name, data, size, flags);
    case 19:
      return unary(&Stub::QueryIrradiance, name, data, size, flags);
    case 20:
      return stream(&Stub::StreamProbes, name, data, size, flags);
    case 21:
      return stream(&Stub::ExportScene, name, data, size, flags);
  }
}

}  // namespace
}  // namespace ddgi::fuzz

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ddgi::fuzz::g_harness = new ddgi::fuzz::Harness();  // lives until the process exits
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ddgi::fuzz;
  if (size < 2) return 0;
  g_harness->prepare();
  dispatch(data[0] % kMethods.size(), data + 2, size - 2, data[1]);
  g_harness->check();
  return 0;
}
