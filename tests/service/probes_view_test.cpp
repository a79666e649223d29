// The probes view over the API (VIEW_MODE_PROBES): it draws the field's probes into the frame,
// and a session without an irradiance field refuses it wherever a view's settings are given
// (CreateView, UpdateView, RenderFrame) with FAILED_PRECONDITION, changing nothing.
#include "encode/jpeg.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

class ProbesViewTest : public ServiceTest {
 protected:
  grpc::Status render_mode(const std::string& session, v1::ViewMode mode, v1::Frame* frame) {
    v1::RenderFrameRequest request;
    request.set_session_id(session);
    request.mutable_settings()->set_width(192);
    request.mutable_settings()->set_height(144);
    request.mutable_settings()->set_view_mode(mode);
    request.mutable_settings()->set_jpeg_quality(100);
    auto ctx = context();
    return stub_->RenderFrame(ctx.get(), request, frame);
  }
};

TEST_F(ProbesViewTest, DrawsTheProbesOverTheFullImage) {
  // 4x4x4 probes, converged (64 updates): the spheres are a few pixels wide at 192x144.
  v1::CreateSessionRequest create = small_session_request("cornell_box", 64);
  add_params(create.mutable_field_params(), {{"counts", "4,4,4"}});
  const std::string session = create_session(create).session_id();
  v1::Frame full, probes;
  ASSERT_TRUE(render_mode(session, v1::VIEW_MODE_FULL, &full).ok());
  const grpc::Status status = render_mode(session, v1::VIEW_MODE_PROBES, &probes);
  ASSERT_TRUE(status.ok()) << status.error_message();
  auto decode = [](const v1::Frame& f) {
    return encode::decode_jpeg(
        std::span(reinterpret_cast<const uint8_t*>(f.jpeg().data()), f.jpeg().size()));
  };
  Result<encode::ImageRgba8> a = decode(full), b = decode(probes);
  ASSERT_TRUE(a.ok() && b.ok());
  // Pixels where the two differ clearly: the probe spheres. The
  // control: two full frames of a converged field differ nowhere near as much.
  auto differing = [](const encode::ImageRgba8& x, const encode::ImageRgba8& y) {
    int count = 0;
    for (size_t i = 0; i < x.pixels.size(); i += 4) {
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(x.pixels[i + c]) - y.pixels[i + c]));
      count += d > 24;
    }
    return count;
  };
  v1::Frame again;
  ASSERT_TRUE(render_mode(session, v1::VIEW_MODE_FULL, &again).ok());
  Result<encode::ImageRgba8> c = decode(again);
  ASSERT_TRUE(c.ok());
  const int spheres = differing(*a, *b), control = differing(*a, *c);
  std::printf("probes view: %d of %d pixels differ from the full image (control: %d)\n", spheres,
              192 * 144, control);
  EXPECT_GT(spheres, 20);
  EXPECT_LT(control, 5);
}

TEST_F(ProbesViewTest, WithoutAFieldItIsRefusedEverywhereAndNothingChanges) {
  v1::CreateSessionRequest create = small_session_request("cornell_box", 0);
  create.set_gi(false);
  create.clear_field_params();
  const std::string session = create_session(create).session_id();
  ASSERT_FALSE(session.empty());

  v1::Frame frame;
  grpc::Status status = render_mode(session, v1::VIEW_MODE_PROBES, &frame);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(status.error_message().find("VIEW_MODE_PROBES needs the irradiance field"),
            std::string::npos)
      << status.error_message();

  v1::CreateViewRequest view_request;
  view_request.set_session_id(session);
  view_request.mutable_settings()->set_view_mode(v1::VIEW_MODE_PROBES);
  v1::ViewInfo view;
  auto ctx = context();
  EXPECT_EQ(stub_->CreateView(ctx.get(), view_request, &view).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);

  view_request.mutable_settings()->set_view_mode(v1::VIEW_MODE_INDIRECT);
  ctx = context();
  ASSERT_TRUE(stub_->CreateView(ctx.get(), view_request, &view).ok());
  v1::UpdateViewRequest update;
  update.set_session_id(session);
  update.set_view_id(view.view_id());
  update.mutable_settings()->set_view_mode(v1::VIEW_MODE_PROBES);
  update.mutable_settings()->set_width(100);
  v1::ViewInfo updated;
  ctx = context();
  EXPECT_EQ(stub_->UpdateView(ctx.get(), update, &updated).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
  // Nothing of the refused update took: neither the mode nor the width that came with it.
  v1::GetSessionRequest get;
  get.set_session_id(session);
  v1::SessionInfo info;
  ctx = context();
  ASSERT_TRUE(stub_->GetSession(ctx.get(), get, &info).ok());
  ASSERT_EQ(info.views_size(), 1);
  EXPECT_EQ(info.views(0).settings().view_mode(), v1::VIEW_MODE_INDIRECT);
  EXPECT_NE(info.views(0).settings().width(), 100u);
}

}  // namespace
}  // namespace ddgi::test
