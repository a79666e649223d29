// GPU faults injected into a running server (issue 18): a memory allocation that fails in the
// middle of a frame, and a lost device. The faults come from vk::Context's test hook, which makes
// the real calls report the injected result; each test runs on a Vulkan context of its own, so
// the loss it injects cannot reach another test's context.
//
// What must hold: an allocation failure ends only the stream whose frame needed the memory, with
// RESOURCE_EXHAUSTED naming the call, and the session serves a new stream once memory is there
// again; a lost device ends every session's streams with UNAVAILABLE naming the loss, turns
// health NOT_SERVING, refuses new sessions with the same message, and the process lives on to
// answer and shut down cleanly (ddgi-server then exits non-zero for its supervisor).
#include <atomic>

#include "grpc/health/v1/health.grpc.pb.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

class GpuFaultTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override {
    options.on_device_lost = [this](const Error&) { device_lost_calls_.fetch_add(1); };
  }
  vk::Context& vulkan() override {
    if (!context_) {
      auto created = create_service_context();
      if (!created.ok()) {
        ADD_FAILURE() << "cannot create a Vulkan context: " << created.error().message;
        return service_context();
      }
      context_ = std::move(created).value();
    }
    return *context_;
  }
  void TearDown() override {
    if (context_) context_->set_test_fault_hook(nullptr);
    ServiceTest::TearDown();
  }

  // Fails every call at `site` with `result` while `armed`.
  void inject(vk::FaultSite site, VkResult result) {
    context_->set_test_fault_hook([this, site, result](vk::FaultSite at) {
      if (at != site || !armed_) return VK_SUCCESS;
      injected_.fetch_add(1);
      return result;
    });
  }

  v1::StreamFramesRequest stream_request(const std::string& session) const {
    v1::StreamFramesRequest request;
    request.set_session_id(session);
    request.mutable_settings()->set_width(64);
    request.mutable_settings()->set_height(48);
    return request;
  }

  grpc::health::v1::HealthCheckResponse::ServingStatus health() {
    auto stub = grpc::health::v1::Health::NewStub(channel_);
    grpc::health::v1::HealthCheckRequest request;
    grpc::health::v1::HealthCheckResponse response;
    auto ctx = context();
    const grpc::Status status = stub->Check(ctx.get(), request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response.status();
  }

  std::unique_ptr<vk::Context> context_;
  std::atomic<bool> armed_{false};
  std::atomic<int> injected_{0};
  std::atomic<int> device_lost_calls_{0};
};

TEST_F(GpuFaultTest, AnAllocationFailureEndsOnlyTheStreamWhoseFrameNeededTheMemory) {
  const std::string a = create_session();
  const std::string b = create_session();
  StreamWatcher steady(*stub_, stream_request(b));
  ASSERT_TRUE(steady.wait_for(3, 60.0)) << "session B's stream never got going";

  // A new stream's first frame allocates its view's targets: that allocation fails.
  inject(vk::FaultSite::kAllocateMemory, VK_ERROR_OUT_OF_DEVICE_MEMORY);
  armed_ = true;
  StreamWatcher failing(*stub_, stream_request(a));
  const grpc::Status ended = failing.wait_end(60.0);
  const uint64_t steady_at_failure = steady.frames();
  std::printf("allocation fault: %d allocations failed; A's stream ended with %d \"%s\"\n",
              injected_.load(), int(ended.error_code()), ended.error_message().c_str());
  EXPECT_EQ(ended.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(ended.error_message().find("vkAllocateMemory"), std::string::npos);
  EXPECT_NE(ended.error_message().find("VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos);
  EXPECT_EQ(failing.frames(), 0u);
  EXPECT_GT(injected_.load(), 0);

  // B kept streaming through it (with the fault still armed: its frames need no allocation).
  EXPECT_TRUE(steady.wait_for(steady_at_failure + 5, 60.0))
      << "session B's stream stopped after session A's allocation failed";
  armed_ = false;

  // With memory back, session A serves a new stream.
  StreamWatcher recovered(*stub_, stream_request(a));
  EXPECT_TRUE(recovered.wait_for(3, 60.0)) << "session A did not recover from the failure";
  EXPECT_EQ(device_lost_calls_.load(), 0);
  EXPECT_EQ(health(), grpc::health::v1::HealthCheckResponse::SERVING);
}

TEST_F(GpuFaultTest, ALostDeviceEndsEverySessionWithAClearStatusAndTheServerLivesOn) {
  const std::string a = create_session();
  const std::string b = create_session();
  StreamWatcher stream_a(*stub_, stream_request(a));
  StreamWatcher stream_b(*stub_, stream_request(b));
  ASSERT_TRUE(stream_a.wait_for(3, 60.0));
  ASSERT_TRUE(stream_b.wait_for(3, 60.0));

  // The next fence wait (some session's frame) reports the device lost, once: the loss itself
  // must then stop every other submission.
  context_->set_test_fault_hook([this](vk::FaultSite at) {
    if (at != vk::FaultSite::kFenceWait || injected_.fetch_add(1) > 0) return VK_SUCCESS;
    return VK_ERROR_DEVICE_LOST;
  });
  const grpc::Status ended_a = stream_a.wait_end(60.0);
  const grpc::Status ended_b = stream_b.wait_end(60.0);
  std::printf("device lost: A ended with %d \"%s\"; B with %d \"%s\"\n", int(ended_a.error_code()),
              ended_a.error_message().c_str(), int(ended_b.error_code()),
              ended_b.error_message().c_str());
  for (const grpc::Status& ended : {ended_a, ended_b}) {
    EXPECT_EQ(ended.error_code(), grpc::StatusCode::UNAVAILABLE);
    EXPECT_NE(ended.error_message().find("GPU device was lost"), std::string::npos);
  }
  EXPECT_TRUE(vulkan().device_lost());
  EXPECT_EQ(device_lost_calls_.load(), 1);
  EXPECT_EQ(health(), grpc::health::v1::HealthCheckResponse::NOT_SERVING);

  // New work is refused with the same message; the server still answers what needs no GPU.
  v1::CreateSessionRequest create = small_session_request("cornell_box", 1);
  v1::SessionInfo info;
  auto ctx = context();
  const grpc::Status refused = stub_->CreateSession(ctx.get(), create, &info);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_NE(refused.error_message().find("GPU device was lost"), std::string::npos);
  v1::GetServerInfoRequest server_request;
  v1::ServerInfo server_info;
  auto info_ctx = context();
  EXPECT_TRUE(stub_->GetServerInfo(info_ctx.get(), server_request, &server_info).ok());
  v1::ListSessionsRequest list_request;
  v1::ListSessionsReply sessions;
  auto list_ctx = context();
  EXPECT_TRUE(stub_->ListSessions(list_ctx.get(), list_request, &sessions).ok());
  EXPECT_EQ(sessions.sessions_size(), 0) << "sessions outlived the device";
}

}  // namespace
}  // namespace ddgi::test
