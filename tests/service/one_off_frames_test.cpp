// One-off frames (RenderFrame without a view id) are bounded per session: at most
// --max-one-off-frames of them are in flight at once (from the call to its reply), and a call
// beyond that is refused at once with RESOURCE_EXHAUSTED naming the limit. Before the bound,
// 48 concurrent one-off calls each built a view and a frame target of their own (hundreds of
// MiB of resident memory on lavapipe). Frames of one size share one target, kept for the next.
#include <condition_variable>
#include <mutex>
#include <vector>

#include "service/one_off_frames.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

constexpr uint32_t kMaxOneOffFrames = 3;

class OneOffFramesTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override {
    options.limits.max_one_off_frames = kMaxOneOffFrames;
    // One frame a second: calls made just after a frame all wait for the next one together.
    options.limits.max_fps = 1;
  }
};

// One asynchronous RenderFrame call.
struct Call {
  grpc::ClientContext context;
  v1::RenderFrameRequest request;
  v1::Frame frame;
  grpc::Status status;
  std::chrono::steady_clock::time_point answered;
};

TEST_F(OneOffFramesTest, AtMostTheLimitInFlightTheRestRefused) {
  const std::string session = create_session();
  // Two frames first: the session's first frame also loads the scene and warms the field, which
  // under the sanitizers takes longer than the one-second pacing, so the frame after it is due at
  // once. The second one is paced, and the next frame is then a second away.
  v1::Frame first;
  ASSERT_TRUE(render(session, 32, 24, &first).ok());
  ASSERT_TRUE(render(session, 32, 24, &first).ok());

  std::mutex mutex;
  std::condition_variable answered;
  size_t done = 0;
  std::vector<std::unique_ptr<Call>> calls;
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t i = 0; i < kMaxOneOffFrames + 1; ++i) {
    auto call = std::make_unique<Call>();
    call->request.set_session_id(session);
    call->request.mutable_settings()->set_width(32);
    call->request.mutable_settings()->set_height(24);
    call->context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    Call* raw = call.get();
    calls.push_back(std::move(call));
    stub_->async()->RenderFrame(&raw->context, &raw->request, &raw->frame,
                                [&, raw](grpc::Status status) {
                                  std::lock_guard<std::mutex> lock(mutex);
                                  raw->status = std::move(status);
                                  raw->answered = std::chrono::steady_clock::now();
                                  ++done;
                                  answered.notify_all();
                                });
  }
  {
    std::unique_lock<std::mutex> lock(mutex);
    ASSERT_TRUE(answered.wait_for(lock, std::chrono::seconds(60), [&] {
      return done == calls.size();
    })) << "not every RenderFrame call was answered";
  }
  uint32_t succeeded = 0, refused = 0;
  for (const auto& call : calls) {
    const double seconds = std::chrono::duration<double>(call->answered - start).count();
    std::printf("one-off call: %s after %.3f s%s%s\n", call->status.ok() ? "frame" : "refused",
                seconds, call->status.ok() ? "" : ": ", call->status.error_message().c_str());
    if (call->status.ok()) {
      ++succeeded;
      EXPECT_EQ(call->frame.frame_index(), first.frame_index() + 1)
          << "the calls in flight share the next frame";
      continue;
    }
    ++refused;
    EXPECT_EQ(call->status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    for (const char* part : {"3 one-off frames in flight", "--max-one-off-frames 3"}) {
      EXPECT_NE(call->status.error_message().find(part), std::string::npos)
          << "'" << part << "' not in: " << call->status.error_message();
    }
  }
  EXPECT_EQ(succeeded, kMaxOneOffFrames) << "as many calls as the limit allows get their frame";
  EXPECT_EQ(refused, 1u) << "the call beyond the limit is refused";

  // Every slot is free again once the replies are out.
  v1::Frame again;
  const grpc::Status status = render(session, 32, 24, &again);
  EXPECT_TRUE(status.ok()) << status.error_message();
}

// Frames of one size share a target; a new size replaces the least recently used one, freed
// before the new one is made, so a session holds at most kKeptTargets of them.
TEST(OneOffTargetsTest, SameSizeSharesATargetAndFewAreKept) {
  vk::Context& context = service_context();
  context.collect_garbage();
  const uint64_t before = context.allocated_bytes();
  {
    service::OneOffFrames frames;
    auto a = frames.target(context, 32, 24);
    ASSERT_TRUE(a.ok()) << a.error().message;
    const uint64_t one_target = context.allocated_bytes() - before;
    auto again = frames.target(context, 32, 24);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(*again, *a) << "the same size reuses its target";
    EXPECT_EQ(context.allocated_bytes() - before, one_target);
    for (uint32_t width : {33u, 34u, 35u, 36u}) {
      ASSERT_TRUE(frames.target(context, width, 24).ok());
    }
    context.collect_garbage();
    EXPECT_LE(context.allocated_bytes() - before,
              service::OneOffFrames::kKeptTargets * one_target * 12 / 10)
        << "more one-off targets kept than kKeptTargets";
    frames.close_all(unavailable("done"));
  }
  context.collect_garbage();
  EXPECT_EQ(context.allocated_bytes(), before) << "close_all frees the kept targets";
}

}  // namespace
}  // namespace ddgi::test
