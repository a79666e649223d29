// Static volumes of a session's irradiance field over RPC (docs/cascades.md): added and removed
// with SetFieldParams (static_volumes), listed among the field's volumes in blend order with what
// placed each, sampled by QueryIrradiance per volume and blended, left in place when the field's
// own grid tracks the camera; a malformed volume is refused by name and changes nothing.
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

using StaticVolumeTest = ServiceTest;

v1::FieldParams set_field(v1::RenderService::Stub& stub, grpc::ClientContext* ctx,
                          const std::string& session, const std::string& name,
                          const std::string& value, grpc::Status* status) {
  v1::SetFieldParamsRequest request;
  request.set_session_id(session);
  v1::FieldParam* param = request.add_params();
  param->set_name(name);
  param->set_value(value);
  v1::FieldParams reply;
  *status = stub.SetFieldParams(ctx, request, &reply);
  return reply;
}

// Red irradiance at (x, 1, 0), normal up: the blend, or one volume alone.
std::vector<float> red_at(v1::RenderService::Stub& stub, grpc::ClientContext* ctx,
                          const std::string& session, std::initializer_list<float> xs,
                          std::optional<uint32_t> volume) {
  v1::QueryIrradianceRequest query;
  query.set_session_id(session);
  for (const float x : xs) {
    v1::QueryPoint* point = query.add_points();
    point->mutable_position()->set_x(x);
    point->mutable_position()->set_y(1.0f);
    point->mutable_normal()->set_y(1.0f);
  }
  if (volume) query.set_volume(*volume);
  v1::QueryIrradianceReply reply;
  const grpc::Status status = stub.QueryIrradiance(ctx, query, &reply);
  EXPECT_TRUE(status.ok()) << status.error_message();
  std::vector<float> red;
  for (const v1::Vec3& e : reply.irradiance()) red.push_back(e.x());
  return red;
}

// The Cornell box with a coarse 4x4x4 grid (1 m, around (0, 1, 0)), tracking the camera. A fine
// static volume (4x4x4, 0.5 m, around the same centre) added by SetFieldParams comes first in
// the list (finer), marked static; the grid second, cascade 0. At the centre the blend is the
// static volume's answer (its weight is 1 within a cell of its centre), at x = 1.1 (past the
// fine grid) the grid's, and the two differ at the centre. A frame from 1.4 m along +x moves
// the grid a cell; the static volume stays. A malformed volume is refused naming it and changes
// nothing; an empty list removes the volume. Planted faults: tracking moving static volumes
// (the static origin moves), the sort ignored (the grid listed first).
TEST_F(StaticVolumeTest, AddedListedSampledLeftInPlaceAndRemoved) {
  v1::CreateSessionRequest request = small_session_request("cornell_box", 1);
  ASSERT_EQ(request.field_params(0).name(), "counts");
  request.mutable_field_params(0)->set_value("4,4,4");
  add_params(request.mutable_field_params(),
             {{"spacing", "1,1,1"}, {"origin", "-1.5,-0.5,-1.5"}, {"track_camera", "true"}});
  const v1::SessionInfo info = create_session(request);
  ASSERT_FALSE(info.session_id().empty());
  const std::string session = info.session_id();
  ASSERT_EQ(info.field().volumes_size(), 1);
  EXPECT_EQ(info.field().volumes(0).cascade(), 0u);
  EXPECT_TRUE(info.field().volumes(0).tracks_camera());

  grpc::Status status;
  v1::FieldParams field = set_field(*stub_, context().get(), session, "static_volumes",
                                    "-0.75,0.25,-0.75/0.5,0.5,0.5/4,4,4", &status);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_EQ(field.volumes_size(), 2);
  EXPECT_EQ(field.probes(), 128u);
  const v1::FieldVolume& fine = field.volumes(0);
  EXPECT_EQ(fine.placed_by_case(), v1::FieldVolume::kStaticVolume);
  EXPECT_EQ(fine.static_volume(), 0u);
  EXPECT_FALSE(fine.tracks_camera());
  EXPECT_EQ(fine.spacing().x(), 0.5f);
  EXPECT_EQ(field.volumes(1).placed_by_case(), v1::FieldVolume::kCascade);
  EXPECT_EQ(field.volumes(1).spacing().x(), 1.0f);

  // Frames warm the field up (the change started it over) with the camera at the centre.
  v1::Frame frame;
  const v1::Camera centre = look_at(0.1f, 1.0f, 0.1f, 0.1f, 1.0f, -1.0f);
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(render(session, 32, 32, &frame, &centre).ok());
  const std::vector<float> blend = red_at(*stub_, context().get(), session, {0.0f, 1.1f}, {});
  const std::vector<float> alone = red_at(*stub_, context().get(), session, {0.0f}, 0u);
  const std::vector<float> grid = red_at(*stub_, context().get(), session, {0.0f, 1.1f}, 1u);
  ASSERT_EQ(blend.size(), 2u);
  std::printf(
      "red at the centre: blend %.5f, static %.5f, grid %.5f; at x = 1.1: blend %.5f, "
      "grid %.5f\n",
      blend[0], alone[0], grid[0], blend[1], grid[1]);
  EXPECT_GT(alone[0], 0.01f);
  EXPECT_NEAR(blend[0], alone[0], 1e-5f);
  EXPECT_NEAR(blend[1], grid[1], 1e-5f);
  EXPECT_GT(std::fabs(alone[0] - grid[0]), 1e-3f);

  const v1::Camera moved = look_at(1.4f, 1.0f, 0.0f, 1.4f, 1.0f, -1.0f);
  ASSERT_TRUE(render(session, 32, 32, &frame, &moved).ok());
  v1::GetFieldParamsRequest get;
  get.set_session_id(session);
  ASSERT_TRUE(stub_->GetFieldParams(context().get(), get, &field).ok());
  ASSERT_EQ(field.volumes_size(), 2);
  EXPECT_EQ(field.volumes(0).origin().x(), -0.75f);  // the static volume stays
  EXPECT_EQ(field.volumes(1).origin().x(), -0.5f);   // the grid moved a cell along +x

  set_field(*stub_, context().get(), session, "static_volumes", "0,0,0/0.5,0.5", &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("static_volumes[0] must be origin/spacing/counts"),
            std::string::npos)
      << status.error_message();
  ASSERT_TRUE(stub_->GetFieldParams(context().get(), get, &field).ok());
  EXPECT_EQ(field.volumes_size(), 2);

  field = set_field(*stub_, context().get(), session, "static_volumes", "", &status);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_EQ(field.volumes_size(), 1);
  EXPECT_EQ(field.probes(), 64u);
  EXPECT_EQ(field.volumes(0).placed_by_case(), v1::FieldVolume::kCascade);
  ASSERT_TRUE(render(session, 32, 32, &frame, &centre).ok());
  EXPECT_GT(mean_level(decode(frame)), 5.0);
}

}  // namespace
}  // namespace ddgi::test
