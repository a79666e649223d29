// Limits each hit once, with the status code and the words of the message, and what the server
// still does afterwards: a frame larger than the send limit, views and lights per session,
// LoadScene with unknown and path-like names, and reflection turned off by its flag.
#include <signal.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "tests/service/reflection_probe.h"
#include "tests/service/server_process.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

constexpr uint64_t kMessageBytes = 64 << 10;  // the least --max-message-bytes allows
constexpr uint32_t kMaxViews = 2;
constexpr uint32_t kMaxLights = 2;  // cornell_box brings one

class ServiceLimitsTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override { configure_limits(options.limits); }
  static void configure_limits(service::ServiceLimits& limits) {
    limits.max_message_bytes = kMessageBytes;
    limits.max_views_per_session = kMaxViews;
    limits.max_lights = kMaxLights;
  }
  static void expect_error(const grpc::Status& status, grpc::StatusCode code,
                           std::initializer_list<std::string> words) {
    EXPECT_EQ(status.error_code(), code) << status.error_message();
    for (const std::string& word : words) {
      EXPECT_NE(status.error_message().find(word), std::string::npos)
          << "message '" << status.error_message() << "' lacks '" << word << "'";
    }
  }
  grpc::Status create_view(const std::string& session, v1::ViewInfo* view) {
    v1::CreateViewRequest request;
    request.set_session_id(session);
    request.mutable_settings()->set_width(16);
    request.mutable_settings()->set_height(12);
    auto ctx = context();
    return stub_->CreateView(ctx.get(), request, view);
  }
  v1::SessionInfo get_session(const std::string& session) {
    v1::GetSessionRequest request;
    request.set_session_id(session);
    v1::SessionInfo info;
    auto ctx = context();
    EXPECT_TRUE(stub_->GetSession(ctx.get(), request, &info).ok());
    return info;
  }
  void expect_renders(const std::string& session) {
    v1::Frame frame;
    const grpc::Status status = render(session, 16, 12, &frame);
    EXPECT_TRUE(status.ok()) << status.error_message();
    EXPECT_FALSE(frame.jpeg().empty());
  }
};

// The encoded size the message names, or 0.
uint64_t encoded_bytes(const std::string& message) {
  const std::string key = "encoded to ";
  const size_t at = message.find(key);
  return at == std::string::npos ? 0 : std::stoull(message.substr(at + key.size()));
}

TEST_F(ServiceLimitsTest, FrameOverTheSendLimit) {
  const std::string session = create_session();
  // An 800x600 frame at JPEG quality 100 encodes to more than 64 KiB.
  v1::RenderFrameRequest request;
  request.set_session_id(session);
  request.mutable_settings()->set_width(800);
  request.mutable_settings()->set_height(600);
  request.mutable_settings()->set_jpeg_quality(100);
  v1::Frame frame;
  auto ctx = context();
  const grpc::Status unary = stub_->RenderFrame(ctx.get(), request, &frame);
  std::printf("oversized frame: %s\n", unary.error_message().c_str());
  expect_error(unary, grpc::StatusCode::RESOURCE_EXHAUSTED,
               {"a 800x600 frame encoded to ", "the message limit of 65536 bytes",
                "--max-message-bytes", "leaves room for 61440", "lower the size or JPEG quality"});
  EXPECT_GT(encoded_bytes(unary.error_message()), 61440u);

  // A stream of such frames ends with the same error; its view goes with it.
  v1::StreamFramesRequest stream;
  stream.set_session_id(session);
  *stream.mutable_settings() = request.settings();
  StreamWatcher watcher(*stub_, stream);
  expect_error(watcher.wait_end(), grpc::StatusCode::RESOURCE_EXHAUSTED,
               {"a 800x600 frame encoded to ", "--max-message-bytes"});
  EXPECT_EQ(watcher.frames(), 0u);
  // Smaller frames of the same session still come, streamed and unary.
  expect_renders(session);
  stream.mutable_settings()->set_width(32);
  stream.mutable_settings()->set_height(24);
  StreamWatcher small(*stub_, stream);
  EXPECT_TRUE(small.wait_for(2, 30.0));
}

TEST_F(ServiceLimitsTest, MaxViewsPerSession) {
  const std::string session = create_session();
  v1::ViewInfo view;
  for (uint32_t i = 0; i < kMaxViews; ++i) ASSERT_TRUE(create_view(session, &view).ok());
  expect_error(create_view(session, &view), grpc::StatusCode::RESOURCE_EXHAUSTED,
               {"already has 2 views", "the most allowed (--max-views-per-session 2)"});
  // A stream that brings its own view counts too.
  v1::StreamFramesRequest stream;
  stream.set_session_id(session);
  stream.mutable_settings()->set_width(16);
  stream.mutable_settings()->set_height(12);
  StreamWatcher watcher(*stub_, stream);
  expect_error(watcher.wait_end(), grpc::StatusCode::RESOURCE_EXHAUSTED,
               {"already has 2 views", "--max-views-per-session 2"});
  EXPECT_EQ(get_session(session).views_size(), int(kMaxViews));
  // One-off frames hold no view: still served. Deleting a view makes room for one.
  expect_renders(session);
  v1::DeleteViewRequest remove;
  remove.set_session_id(session);
  remove.set_view_id(view.view_id());
  v1::DeleteViewReply removed;
  auto ctx = context();
  ASSERT_TRUE(stub_->DeleteView(ctx.get(), remove, &removed).ok());
  EXPECT_TRUE(create_view(session, &view).ok());
}

TEST_F(ServiceLimitsTest, MaxLights) {
  const std::string session = create_session();
  ASSERT_EQ(get_session(session).lights_size(), 1);
  v1::AddLightRequest add;
  add.set_session_id(session);
  add.mutable_light()->set_type(v1::LIGHT_TYPE_POINT);
  add.mutable_light()->set_intensity(1.0f);
  v1::LightReply reply;
  auto ctx = context();
  ASSERT_TRUE(stub_->AddLight(ctx.get(), add, &reply).ok());
  ctx = context();
  expect_error(stub_->AddLight(ctx.get(), add, &reply), grpc::StatusCode::RESOURCE_EXHAUSTED,
               {"already has 2 lights", "the most allowed (--max-lights 2)"});
  EXPECT_EQ(get_session(session).lights_size(), 2);
  expect_renders(session);
}

TEST_F(ServiceLimitsTest, LoadSceneUnknownOrPathLikeName) {
  const std::string session = create_session();
  auto load = [&](const std::string& name) {
    v1::LoadSceneRequest request;
    request.set_session_id(session);
    request.mutable_scene()->set_name(name);
    v1::SessionInfo info;
    auto ctx = context();
    return stub_->LoadScene(ctx.get(), request, &info);
  };
  expect_error(load("no_such_scene"), grpc::StatusCode::NOT_FOUND,
               {"no scene named 'no_such_scene'", "GetServerInfo"});
  for (const char* name : {"../cornell_box", "/etc/passwd", "scenes/cornell_box", ".hidden"}) {
    SCOPED_TRACE(name);
    expect_error(load(name), grpc::StatusCode::INVALID_ARGUMENT, {"looks like a path"});
  }
  expect_error(load(std::string("cornell_box\0x", 13)), grpc::StatusCode::INVALID_ARGUMENT,
               {"NUL byte"});
  // The session keeps its scene and keeps rendering.
  const v1::SessionInfo info = get_session(session);
  EXPECT_EQ(info.scene(), "cornell_box");
  EXPECT_GT(info.triangles(), 0u);
  expect_renders(session);
}

// Pads a request with an unknown length-delimited field (field 1000, which no request has) so
// that it serializes to about `bytes`.
template <typename Request>
Request padded(Request request, size_t bytes) {
  const size_t base = request.ByteSizeLong();
  const size_t pad = bytes > base + 8 ? bytes - base - 8 : 0;
  request.GetReflection()->MutableUnknownFields(&request)->AddLengthDelimited(1000)->assign(pad,
                                                                                            'x');
  return request;
}

// The receive limit is a property of the gRPC server, not of a method: gRPC C++ has no
// per-method receive limit on the server (its message-size filter takes per-method limits only
// from a client's service config), so every RPC accepts a request as large as an upload
// (docs/service.md, "Limits and their errors"). This pins the limit each RPC has: a request of
// twice --max-message-bytes reaches the handler (refused for what it says, never for its size),
// one a KiB over max_receive_bytes is refused by gRPC before any handler runs.
TEST_F(ServiceLimitsTest, ReceiveLimitIsTheSameForEveryRpc) {
  service::ServiceLimits limits = test_server_options().limits;
  configure_limits(limits);
  const uint64_t receive = service::max_receive_bytes(limits);
  ASSERT_GT(receive, 2 * kMessageBytes);
  std::printf("--max-message-bytes %llu, receive limit %llu bytes\n",
              static_cast<unsigned long long>(kMessageBytes),
              static_cast<unsigned long long>(receive));
  v1::RenderService::Stub& stub = *stub_;
  // Each sends a request of about `bytes` and returns how the call ended.
  auto unary = [&](auto method, auto request, auto reply) {
    return [&stub, method, request, reply](size_t bytes) mutable {
      grpc::ClientContext ctx;
      ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
      return (stub.*method)(&ctx, padded(request, bytes), &reply);
    };
  };
  auto streaming = [&](auto method, auto request, auto reply) {
    return [&stub, method, request, reply](size_t bytes) mutable {
      grpc::ClientContext ctx;
      ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
      auto reader = (stub.*method)(&ctx, padded(request, bytes));
      while (reader->Read(&reply)) {
      }
      return reader->Finish();
    };
  };
  v1::GetSessionRequest get_session;
  get_session.set_session_id("s-unknown");
  v1::StreamFramesRequest stream;
  stream.set_session_id("s-unknown");
  v1::DumpAtlasRequest dump;
  dump.set_session_id("s-unknown");
  v1::SetCameraRequest camera;
  camera.set_session_id("s-unknown");
  const std::vector<std::pair<const char*, std::function<grpc::Status(size_t)>>> rpcs = {
      {"GetServerInfo", unary(&v1::RenderService::Stub::GetServerInfo, v1::GetServerInfoRequest(),
                              v1::ServerInfo())},
      {"CreateSession", unary(&v1::RenderService::Stub::CreateSession, v1::CreateSessionRequest(),
                              v1::SessionInfo())},
      {"LoadScene",
       unary(&v1::RenderService::Stub::LoadScene, v1::LoadSceneRequest(), v1::SessionInfo())},
      {"ListSessions", unary(&v1::RenderService::Stub::ListSessions, v1::ListSessionsRequest(),
                             v1::ListSessionsReply())},
      {"GetSession", unary(&v1::RenderService::Stub::GetSession, get_session, v1::SessionInfo())},
      {"SetCamera", unary(&v1::RenderService::Stub::SetCamera, camera, v1::ViewInfo())},
      {"StreamFrames", streaming(&v1::RenderService::Stub::StreamFrames, stream, v1::Frame())},
      {"DumpAtlas", streaming(&v1::RenderService::Stub::DumpAtlas, dump, v1::AtlasChunk())},
  };
  for (const auto& [name, call] : rpcs) {
    SCOPED_TRACE(name);
    const grpc::Status under = call(2 * kMessageBytes);
    EXPECT_NE(under.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << under.error_message();
    const grpc::Status over = call(receive + 1024);
    expect_error(over, grpc::StatusCode::RESOURCE_EXHAUSTED, {"Received message larger than max"});
    std::printf("%-14s %7llu bytes: code %2d; %7llu bytes: code %2d '%s'\n", name,
                static_cast<unsigned long long>(2 * kMessageBytes), int(under.error_code()),
                static_cast<unsigned long long>(receive + 1024), int(over.error_code()),
                over.error_message().c_str());
  }
}

// Reflection's plugin is process-wide once registered, so the flag is tested on a process.
TEST(ServiceLimitsProcessTest, NoReflectionFlagAnswersUnimplemented) {
  ServerProcess process({"--no-reflection"});
  const int port = process.port();
  ASSERT_GT(port, 0) << "ddgi-server did not start";
  auto channel =
      grpc::CreateChannel("127.0.0.1:" + std::to_string(port), grpc::InsecureChannelCredentials());
  const ReflectionAnswer answer = list_services(channel);
  std::printf("reflection with --no-reflection: code %d, '%s'\n", int(answer.status.error_code()),
              answer.status.error_message().c_str());
  EXPECT_EQ(answer.status.error_code(), grpc::StatusCode::UNIMPLEMENTED);
  EXPECT_EQ(answer.text.find("ddgi.v1.RenderService"), std::string::npos);
  // The service itself answers.
  auto stub = v1::RenderService::NewStub(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
  v1::ServerInfo info;
  EXPECT_TRUE(stub->GetServerInfo(&ctx, {}, &info).ok());
  process.signal(SIGTERM);
  EXPECT_EQ(process.wait(10.0), 0);
}

}  // namespace
}  // namespace ddgi::test
