// A refused SetFieldParams loses nothing: a grid over the GPU budget, or a request with one
// bad value, leaves the session's field exactly as it was (atlas bytes, GPU bytes, update
// count), and the field keeps updating afterwards. Both fields (irradiance and shadow).
#include <string>
#include <vector>

#include "gi/field_params.h"
#include "gi/shadow_params.h"
#include "tests/service/atlas_download.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

class FieldRefusalTest : public ServiceTest {
 protected:
  v1::FieldParams get_params(const std::string& session, v1::FieldKind kind) {
    v1::GetFieldParamsRequest request;
    request.set_session_id(session);
    request.set_field(kind);
    v1::FieldParams reply;
    auto ctx = context();
    const grpc::Status status = stub_->GetFieldParams(ctx.get(), request, &reply);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return reply;
  }
  grpc::Status set_params(const std::string& session, v1::FieldKind kind,
                          const std::vector<std::pair<std::string, std::string>>& params) {
    v1::SetFieldParamsRequest request;
    request.set_session_id(session);
    request.set_field(kind);
    for (const auto& [name, value] : params) {
      auto* p = request.add_params();
      p->set_name(name);
      p->set_value(value);
    }
    v1::FieldParams reply;
    auto ctx = context();
    return stub_->SetFieldParams(ctx.get(), request, &reply);
  }
  // The reply's parameters as "name=value" assignments, to rebuild the struct in effect.
  static std::vector<std::string> assignments(const v1::FieldParams& params) {
    std::vector<std::string> out;
    for (const auto& p : params.params()) out.push_back(p.name() + "=" + p.value());
    return out;
  }
  std::string make_view(const std::string& session) {
    v1::CreateViewRequest request;
    request.set_session_id(session);
    request.mutable_settings()->set_width(16);
    request.mutable_settings()->set_height(12);
    v1::ViewInfo view;
    auto ctx = context();
    EXPECT_TRUE(stub_->CreateView(ctx.get(), request, &view).ok());
    return view.view_id();
  }
  v1::Frame render_view(const std::string& session, const std::string& view) {
    v1::RenderFrameRequest request;
    request.set_session_id(session);
    request.set_view_id(view);
    v1::Frame frame;
    auto ctx = context();
    const grpc::Status status = stub_->RenderFrame(ctx.get(), request, &frame);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return frame;
  }
  // Both numbers of the budget refusal appear in the message as the decimal byte counts.
  static void expect_names_bytes(const grpc::Status& status, uint64_t needed, uint64_t held) {
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
    const std::string& message = status.error_message();
    EXPECT_NE(message.find("needs " + std::to_string(needed) + " bytes"), std::string::npos)
        << message;
    EXPECT_NE(message.find("of the " + std::to_string(kTestGpuBudget) + "-byte budget"),
              std::string::npos)
        << message;
    // What it says is free is less than the need (else the refusal would be wrong) and at least
    // the field's own bytes (they are given back when a grid is replaced).
    const size_t free_end = message.find(" bytes of the ");
    ASSERT_NE(free_end, std::string::npos) << message;
    const size_t free_start = message.rfind(' ', free_end - 1) + 1;
    const uint64_t free = std::stoull(message.substr(free_start, free_end - free_start));
    EXPECT_LT(free, needed);
    EXPECT_GE(free, held);
    EXPECT_LE(free, kTestGpuBudget);
  }
};

TEST_F(FieldRefusalTest, IrradianceFieldKeptByteForByte) {
  const std::string session = create_session("cornell_box", 3);
  const std::string view = make_view(session);
  const v1::FieldParams before = get_params(session, v1::FIELD_KIND_IRRADIANCE);
  const AtlasDownload atlas_before =
      download_atlas(*stub_, session, v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_FORMAT_RAW_F32);
  const AtlasDownload distance_before =
      download_atlas(*stub_, session, v1::ATLAS_KIND_DISTANCE, v1::ATLAS_FORMAT_RAW_F32);
  ASSERT_TRUE(atlas_before.status.ok()) << atlas_before.status.error_message();
  ASSERT_TRUE(distance_before.status.ok());
  ASSERT_EQ(atlas_before.bytes.size(), atlas_before.metadata.total_bytes());
  ASSERT_EQ(before.updates(), 3u);

  // The need the server must name: the parameters in effect with a 64^3 grid.
  IrradianceFieldParams huge;
  ASSERT_TRUE(field_param_table().apply(huge, assignments(before)).ok());
  ASSERT_TRUE(field_param_table().apply(huge, {"counts=64,64,64"}).ok());
  ASSERT_TRUE(validate(huge).ok()) << "the request must be refused by the budget, not a range";
  const uint64_t needed = field_gpu_bytes(huge);
  ASSERT_GT(needed, kTestGpuBudget);

  const grpc::Status refused =
      set_params(session, v1::FIELD_KIND_IRRADIANCE, {{"counts", "64,64,64"}});
  expect_names_bytes(refused, needed, before.gpu_bytes());
  EXPECT_NE(refused.error_message().find("64x64x64 probes"), std::string::npos);

  // Refused by validation: one good value next to a bad one changes nothing either.
  const grpc::Status invalid =
      set_params(session, v1::FIELD_KIND_IRRADIANCE, {{"counts", "3,3,3"}, {"hysteresis", "1.5"}});
  EXPECT_EQ(invalid.error_code(), grpc::StatusCode::INVALID_ARGUMENT);

  const v1::FieldParams after = get_params(session, v1::FIELD_KIND_IRRADIANCE);
  EXPECT_EQ(after.gpu_bytes(), before.gpu_bytes());
  EXPECT_EQ(after.probes(), 8u);
  EXPECT_EQ(after.updates(), before.updates()) << "the field started over";
  EXPECT_EQ(assignments(after), assignments(before));
  const AtlasDownload atlas_after =
      download_atlas(*stub_, session, v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_FORMAT_RAW_F32);
  const AtlasDownload distance_after =
      download_atlas(*stub_, session, v1::ATLAS_KIND_DISTANCE, v1::ATLAS_FORMAT_RAW_F32);
  ASSERT_TRUE(atlas_after.status.ok());
  EXPECT_TRUE(atlas_after.bytes == atlas_before.bytes) << "the irradiance history changed";
  EXPECT_TRUE(distance_after.bytes == distance_before.bytes) << "the distance history changed";
  EXPECT_EQ(atlas_after.metadata.field_updates(), 3u);

  // The field is alive: the next frame updates it once more, and the history moves on.
  const v1::Frame frame = render_view(session, view);
  EXPECT_EQ(frame.field_updates(), before.updates() + 1);
  EXPECT_GT(frame.gi_update_ms(), 0.0);
  const AtlasDownload updated =
      download_atlas(*stub_, session, v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_FORMAT_RAW_F32);
  EXPECT_EQ(updated.metadata.field_updates(), before.updates() + 1);
  EXPECT_FALSE(updated.bytes == atlas_before.bytes) << "an update changed nothing";
}

TEST_F(FieldRefusalTest, ShadowFieldKeptByteForByte) {
  const v1::SessionInfo info = create_session(small_shadow_field_session_request("cornell_box", 2));
  ASSERT_FALSE(info.session_id().empty());
  const std::string session = info.session_id();
  const std::string view = make_view(session);
  const v1::FieldParams before = get_params(session, v1::FIELD_KIND_SHADOW);
  const AtlasDownload visibility_before =
      download_atlas(*stub_, session, v1::ATLAS_KIND_SHADOW, v1::ATLAS_FORMAT_RAW_F32);
  const AtlasDownload moments_before =
      download_atlas(*stub_, session, v1::ATLAS_KIND_SHADOW_MOMENTS, v1::ATLAS_FORMAT_RAW_F32);
  ASSERT_TRUE(visibility_before.status.ok()) << visibility_before.status.error_message();
  ASSERT_FALSE(visibility_before.bytes.empty());

  ShadowFieldParams huge;
  ASSERT_TRUE(shadow_param_table().apply(huge, assignments(before)).ok());
  ASSERT_TRUE(shadow_param_table().apply(huge, {"counts=32,32,32", "rays_per_probe=1024"}).ok());
  ASSERT_TRUE(validate(huge).ok()) << "the request must be refused by the budget, not a range";
  const uint64_t needed = shadow_field_gpu_bytes(huge);
  ASSERT_GT(needed, kTestGpuBudget);

  const grpc::Status refused = set_params(session, v1::FIELD_KIND_SHADOW,
                                          {{"counts", "32,32,32"}, {"rays_per_probe", "1024"}});
  expect_names_bytes(refused, needed, before.gpu_bytes());
  EXPECT_NE(refused.error_message().find("shadow field (32x32x32 probes"), std::string::npos);

  const v1::FieldParams after = get_params(session, v1::FIELD_KIND_SHADOW);
  EXPECT_EQ(after.gpu_bytes(), before.gpu_bytes());
  EXPECT_EQ(after.probes(), 27u);
  EXPECT_EQ(after.updates(), before.updates()) << "the shadow field started over";
  EXPECT_EQ(assignments(after), assignments(before));
  const AtlasDownload visibility_after =
      download_atlas(*stub_, session, v1::ATLAS_KIND_SHADOW, v1::ATLAS_FORMAT_RAW_F32);
  const AtlasDownload moments_after =
      download_atlas(*stub_, session, v1::ATLAS_KIND_SHADOW_MOMENTS, v1::ATLAS_FORMAT_RAW_F32);
  EXPECT_TRUE(visibility_after.bytes == visibility_before.bytes) << "the visibility changed";
  EXPECT_TRUE(moments_after.bytes == moments_before.bytes) << "the moments history changed";

  const v1::Frame frame = render_view(session, view);
  EXPECT_FALSE(frame.jpeg().empty());
  EXPECT_EQ(get_params(session, v1::FIELD_KIND_SHADOW).updates(), before.updates() + 1);
  const AtlasDownload updated =
      download_atlas(*stub_, session, v1::ATLAS_KIND_SHADOW_MOMENTS, v1::ATLAS_FORMAT_RAW_F32);
  EXPECT_FALSE(updated.bytes == moments_before.bytes) << "an update changed nothing";
}

}  // namespace
}  // namespace ddgi::test
