// SIGTERM with live streams, on a real ddgi-server process: health turns NOT_SERVING, every
// stream ends with OK (a clean end, not a dropped connection), and the process exits 0 within
// its shutdown grace period.
#include <signal.h>

#include "grpc/health/v1/health.grpc.pb.h"
#include "tests/service/server_process.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

using Clock = std::chrono::steady_clock;

TEST(ShutdownTest, SigtermEndsStreamsCleanlyAndExitsInTime) {
  constexpr double kGrace = 3.0;
  ServerProcess process({"--shutdown-grace", "3", "--max-fps", "20"});
  const int port = process.port();
  ASSERT_GT(port, 0) << "ddgi-server did not start";
  auto channel =
      grpc::CreateChannel("127.0.0.1:" + std::to_string(port), grpc::InsecureChannelCredentials());
  auto stub = v1::RenderService::NewStub(channel);
  v1::CreateSessionRequest create;
  create.mutable_scene()->set_name("cornell_box");
  create.set_warmup_updates(1);
  for (auto [name, value] : {std::pair{"counts", "2,2,2"}, {"rays_per_probe", "16"}}) {
    auto* p = create.add_field_params();
    p->set_name(name);
    p->set_value(value);
  }
  v1::SessionInfo session;
  {
    grpc::ClientContext ctx;
    ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    const grpc::Status status = stub->CreateSession(&ctx, create, &session);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  std::vector<std::unique_ptr<StreamWatcher>> streams;
  for (int i = 0; i < 2; ++i) {
    v1::StreamFramesRequest request;
    request.set_session_id(session.session_id());
    request.mutable_settings()->set_width(32);
    request.mutable_settings()->set_height(24);
    streams.push_back(std::make_unique<StreamWatcher>(*stub, request));
  }
  for (auto& stream : streams) ASSERT_TRUE(stream->wait_for(2, 30.0));

  // Watch health from before the signal: it must go from SERVING to NOT_SERVING.
  auto health = grpc::health::v1::Health::NewStub(channel);
  grpc::ClientContext watch_context;
  auto watch = health->Watch(&watch_context, grpc::health::v1::HealthCheckRequest());
  grpc::health::v1::HealthCheckResponse response;
  ASSERT_TRUE(watch->Read(&response));
  EXPECT_EQ(response.status(), grpc::health::v1::HealthCheckResponse::SERVING);

  const auto signalled = Clock::now();
  process.signal(SIGTERM);
  bool saw_not_serving = false;
  while (watch->Read(&response)) {
    if (response.status() == grpc::health::v1::HealthCheckResponse::NOT_SERVING) {
      saw_not_serving = true;
      break;
    }
  }
  EXPECT_TRUE(saw_not_serving);
  for (auto& stream : streams) {
    const grpc::Status status = stream->wait_end(kGrace + 2.0);
    EXPECT_TRUE(status.ok()) << "a stream did not end cleanly: " << status.error_code() << " "
                             << status.error_message();
  }
  const int exit_code = process.wait(kGrace + 5.0);
  const double seconds = std::chrono::duration<double>(Clock::now() - signalled).count();
  std::printf("SIGTERM to exit: %.2f s (grace %.0f s)\n", seconds, kGrace);
  EXPECT_EQ(exit_code, 0) << "ddgi-server exited badly (validation messages?) or hung";
  EXPECT_LT(seconds, kGrace + 1.5);
  watch_context.TryCancel();
  (void)watch->Finish();
}

}  // namespace
}  // namespace ddgi::test
