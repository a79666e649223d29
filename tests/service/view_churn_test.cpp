// Creating and deleting views must not stall a session. CreateView used to build a renderer's
// kernels on the session's loop thread (100-270 ms each), so a client churning views froze
// every stream of its session; now a view is settings and a camera until its first frame. Here
// one client streams from a session while another creates and deletes views on it as fast as
// it can (loopback, bounded in time and count); the stream must keep most of its rate.
#include <thread>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

// Measured on lavapipe, 2 shared CPU cores, --max-fps 25, a 64x48 stream (the printed line),
// three runs: 24.7 fps before; 25.0, 25.0 and 24.7 fps during 3 s of churn at 1000-1400
// CreateView+DeleteView pairs a second (CreateView 0.36-0.49 ms mean, 11-15 ms at most); the
// loop takes a command between frames, and a view costs no GPU work until its first frame.
// The bound is 70% of the rate before. On the code before views shared the session's renderer
// (ecfe2aa) this test fails: 24.7 fps before, 9.3 and 10.0 fps during, 10 pairs a second,
// CreateView 93-98 ms mean and 128-129 ms at most.
constexpr double kKeptFraction = 0.7;
constexpr double kSeconds = 3.0;
constexpr int kMaxPairs = 20000;

class ViewChurnTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override { options.limits.max_fps = 25; }
};

struct ChurnResult {
  int pairs = 0;
  double seconds = 0.0;
  double create_ms_total = 0.0;
  double create_ms_max = 0.0;
  std::string error;
};

// CreateView + DeleteView on `session` until `stop` (or kMaxPairs), on its own connection.
ChurnResult churn_views(const std::string& address, const std::string& session,
                        const std::atomic<bool>& stop) {
  auto channel = grpc::CreateChannel(address, grpc::InsecureChannelCredentials());
  auto stub = v1::RenderService::NewStub(channel);
  ChurnResult result;
  const auto start = std::chrono::steady_clock::now();
  while (!stop && result.pairs < kMaxPairs) {
    v1::CreateViewRequest create;
    create.set_session_id(session);
    create.mutable_settings()->set_width(640);
    create.mutable_settings()->set_height(480);
    *create.mutable_camera() = look_at(0.3f, 0.8f, 1.2f, 0.0f, 0.5f, 0.0f);
    v1::ViewInfo view;
    grpc::ClientContext create_context;
    const auto sent = std::chrono::steady_clock::now();
    grpc::Status status = stub->CreateView(&create_context, create, &view);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count();
    if (!status.ok()) {
      result.error = "CreateView: " + status.error_message();
      break;
    }
    result.create_ms_total += ms;
    result.create_ms_max = std::max(result.create_ms_max, ms);
    v1::DeleteViewRequest remove;
    remove.set_session_id(session);
    remove.set_view_id(view.view_id());
    v1::DeleteViewReply removed;
    grpc::ClientContext delete_context;
    status = stub->DeleteView(&delete_context, remove, &removed);
    if (!status.ok()) {
      result.error = "DeleteView: " + status.error_message();
      break;
    }
    ++result.pairs;
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

TEST_F(ViewChurnTest, CreatingAndDeletingViewsKeepsAnotherClientsStreamRate) {
  const std::string session = create_session();
  auto stream_channel = grpc::CreateChannel(address(), grpc::InsecureChannelCredentials());
  auto stream_stub = v1::RenderService::NewStub(stream_channel);
  v1::StreamFramesRequest request;
  request.set_session_id(session);
  request.mutable_settings()->set_width(64);
  request.mutable_settings()->set_height(48);
  StreamWatcher stream(*stream_stub, request);
  ASSERT_TRUE(stream.wait_for(5, 30.0)) << "the stream never got going";

  const double fps_before = stream.measure_fps(kSeconds);
  std::atomic<bool> stop{false};
  ChurnResult churn;
  std::thread churner([&] { churn = churn_views(address(), session, stop); });
  const double fps_during = stream.measure_fps(kSeconds);
  stop = true;
  churner.join();
  const double fps_after = stream.measure_fps(1.0);

  std::printf(
      "view churn: stream %.1f fps before, %.1f fps during %d CreateView+DeleteView pairs in "
      "%.1f s (%.0f pairs/s; CreateView %.2f ms mean, %.1f ms max), %.1f fps after\n",
      fps_before, fps_during, churn.pairs, churn.seconds, churn.pairs / churn.seconds,
      churn.pairs ? churn.create_ms_total / churn.pairs : 0.0, churn.create_ms_max, fps_after);
  EXPECT_TRUE(churn.error.empty()) << churn.error;
  EXPECT_GT(churn.pairs, 20) << "the churning client hardly got through";
  EXPECT_GT(fps_before, 5.0) << "the stream never reached a rate worth comparing";
  EXPECT_GE(fps_during, kKeptFraction * fps_before)
      << "creating and deleting views slowed another client's stream on the session";
}

}  // namespace
}  // namespace ddgi::test
