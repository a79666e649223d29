// SIGTERM with live streams, on a real ddgi-server process: health turns NOT_SERVING, every
// stream ends with OK (a clean end, not a dropped connection), and the process exits 0 within
// its shutdown grace period.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>

#include "grpc/health/v1/health.grpc.pb.h"
#include "tests/service/service_fixture.h"

extern char** environ;

namespace ddgi::test {
namespace {

using Clock = std::chrono::steady_clock;

class ServerProcess {
 public:
  explicit ServerProcess(const std::vector<std::string>& extra) {
    port_file_ = testing::TempDir() + "/ddgi_port_" + std::to_string(::getpid());
    std::remove(port_file_.c_str());
    std::vector<std::string> args = {
        DDGI_SERVER_EXECUTABLE, "--listen", "127.0.0.1:0",  "--port-file",        port_file_,
        "--metrics-port",       "-1",       "--scene-root", DDGI_TEST_SCENE_ROOT, "--validation"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    EXPECT_EQ(posix_spawn(&pid_, argv[0], nullptr, nullptr, argv.data(), environ), 0);
  }
  ~ServerProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    std::remove(port_file_.c_str());
  }
  // The port, once the server wrote it (0 on timeout).
  int port(double timeout_seconds = 60.0) {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_seconds);
    while (Clock::now() < end) {
      std::ifstream file(port_file_);
      int port = 0;
      if (file >> port && port > 0) return port;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return 0;
  }
  void signal(int number) { ::kill(pid_, number); }
  // The exit status, or -1 when the process is still running after `timeout_seconds`.
  int wait(double timeout_seconds) {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_seconds);
    while (Clock::now() < end) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  std::string port_file_;
};

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
