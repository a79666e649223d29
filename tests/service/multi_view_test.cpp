// Several clients on one session: two views with their own cameras stream at once. Each frame
// carries its own view's camera and id, the two images differ, and the field is updated once
// per frame-loop iteration however many views it renders (GI is computed once per session).
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

bool wait_until(const std::function<bool()>& done, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

double mean_abs_difference(const encode::ImageRgba8& a, const encode::ImageRgba8& b) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i) {
    if (i % 4 == 3) continue;  // alpha
    sum += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    ++count;
  }
  return count ? sum / double(count) : 0.0;
}

class MultiViewTest : public ServiceTest {
 protected:
  v1::ViewInfo create_view(const std::string& session, const v1::Camera& camera) {
    v1::CreateViewRequest request;
    request.set_session_id(session);
    request.mutable_settings()->set_width(40);
    request.mutable_settings()->set_height(30);
    *request.mutable_camera() = camera;
    v1::ViewInfo view;
    auto ctx = context();
    const grpc::Status status = stub_->CreateView(ctx.get(), request, &view);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return view;
  }
  uint64_t session_frames(const std::string& session) {
    v1::GetSessionRequest request;
    request.set_session_id(session);
    v1::SessionInfo info;
    auto ctx = context();
    EXPECT_TRUE(stub_->GetSession(ctx.get(), request, &info).ok());
    return info.frames();
  }
};

TEST_F(MultiViewTest, TwoViewsOwnCamerasOneFieldUpdatePerFrame) {
  const std::string session = create_session("cornell_box", 2);
  const v1::Camera camera_a = look_at(0.0f, 0.5f, 1.6f, 0.0f, 0.5f, 0.0f, 40.0f);
  const v1::Camera camera_b = look_at(0.3f, 0.8f, 1.2f, -0.2f, 0.3f, 0.0f, 60.0f);
  const v1::ViewInfo view_a = create_view(session, camera_a);
  const v1::ViewInfo view_b = create_view(session, camera_b);
  ASSERT_NE(view_a.view_id(), view_b.view_id());

  const uint64_t updates_before = server().metrics().field_updates.load();
  const uint64_t rendered_before = server().metrics().frames_rendered.load();
  const uint64_t loop_frames_before = session_frames(session);
  std::map<std::string, std::unique_ptr<StreamWatcher>> streams;
  for (const v1::ViewInfo* view : {&view_a, &view_b}) {
    v1::StreamFramesRequest request;
    request.set_session_id(session);
    request.set_view_id(view->view_id());
    streams[view->view_id()] = std::make_unique<StreamWatcher>(*stub_, request, token_, true);
  }
  ASSERT_TRUE(wait_until(
      [&] {
        return streams[view_a.view_id()]->frames() >= 8 && streams[view_b.view_id()]->frames() >= 8;
      },
      60.0))
      << "the two streams did not both deliver 8 frames";
  for (auto& [id, stream] : streams) stream->stop();
  // The loop is idle once nobody waits for frames; wait for its last iteration to be counted.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const uint64_t loop_frames = session_frames(session) - loop_frames_before;
  const uint64_t updates = server().metrics().field_updates.load() - updates_before;
  const uint64_t rendered = server().metrics().frames_rendered.load() - rendered_before;
  std::printf("two views: %llu loop iterations, %llu field updates, %llu view frames rendered\n",
              static_cast<unsigned long long>(loop_frames),
              static_cast<unsigned long long>(updates), static_cast<unsigned long long>(rendered));
  // One update per iteration, while most iterations rendered both views.
  EXPECT_EQ(updates, loop_frames);
  EXPECT_GE(loop_frames, 8u);
  EXPECT_GT(rendered, loop_frames + loop_frames / 2);

  // Per frame: its view's camera and id, and field_updates - frame_index the same for every
  // frame of both views (an update per view would add one between the two views' frames of an
  // iteration, and two per iteration).
  std::map<uint64_t, std::map<std::string, v1::Frame>> by_index;
  std::optional<int64_t> offset;
  for (const v1::ViewInfo* view : {&view_a, &view_b}) {
    const v1::Camera& camera = view == &view_a ? camera_a : camera_b;
    for (const v1::Frame& frame : streams[view->view_id()]->all()) {
      SCOPED_TRACE("view " + view->view_id() + " frame " + std::to_string(frame.frame_index()));
      EXPECT_EQ(frame.view_id(), view->view_id());
      EXPECT_EQ(frame.session_id(), session);
      EXPECT_NEAR(frame.camera().position().x(), camera.position().x(), 1e-6f);
      EXPECT_NEAR(frame.camera().position().y(), camera.position().y(), 1e-6f);
      EXPECT_NEAR(frame.camera().position().z(), camera.position().z(), 1e-6f);
      EXPECT_NEAR(frame.camera().vertical_fov_degrees(), camera.vertical_fov_degrees(), 1e-4f);
      const int64_t frame_offset = int64_t(frame.field_updates()) - int64_t(frame.frame_index());
      if (!offset) offset = frame_offset;
      EXPECT_EQ(frame_offset, *offset) << "field updates " << frame.field_updates();
      by_index[frame.frame_index()][view->view_id()] = frame;
    }
  }
  ASSERT_TRUE(offset.has_value());
  EXPECT_EQ(*offset, 2) << "the warm-up's 2 updates, then one per frame";

  // The two views of one iteration show different pictures.
  bool compared = false;
  for (const auto& [index, frames] : by_index) {
    if (frames.size() != 2) continue;
    const double difference = mean_abs_difference(decode(frames.at(view_a.view_id())),
                                                  decode(frames.at(view_b.view_id())));
    std::printf("frame %llu: views differ by %.1f levels of 255 on average\n",
                static_cast<unsigned long long>(index), difference);
    EXPECT_GT(difference, 5.0) << "the two cameras' images are (nearly) the same";
    compared = true;
    break;
  }
  EXPECT_TRUE(compared) << "no iteration delivered a frame to both views";
}

}  // namespace
}  // namespace ddgi::test
