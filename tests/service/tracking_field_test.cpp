// A session's tracking field over RPC (docs/cascades.md): with track_camera the field's grid
// follows the camera of the frames that carry its updates in whole cells, GetFieldParams shows
// where it is now, and dumps give probes in grid order from the new origin (the probes that
// stayed are where the grid says they are).
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "tests/service/atlas_download.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

using TrackingFieldTest = ServiceTest;

// The field's origin as GetFieldParams reports it.
glm::vec3 field_origin(v1::RenderService::Stub& stub, const std::string& session,
                       grpc::ClientContext* ctx) {
  v1::GetFieldParamsRequest get;
  get.set_session_id(session);
  v1::FieldParams params;
  EXPECT_TRUE(stub.GetFieldParams(ctx, get, &params).ok());
  for (const v1::FieldParam& p : params.params()) {
    glm::vec3 origin(0.0f);
    if (p.name() == "origin" &&
        std::sscanf(p.value().c_str(), "%f,%f,%f", &origin.x, &origin.y, &origin.z) == 3) {
      return origin;
    }
  }
  ADD_FAILURE() << "no origin in GetFieldParams";
  return glm::vec3(0.0f);
}

std::vector<float> probe_state_texels(v1::RenderService::Stub& stub, const std::string& session) {
  const AtlasDownload dump =
      download_atlas(stub, session, v1::ATLAS_KIND_PROBE_STATES, v1::ATLAS_FORMAT_RAW_F32);
  EXPECT_TRUE(dump.status.ok()) << dump.status.error_message();
  return raw_floats(dump.bytes);
}

// A 4x4x4 grid 0.5 m apart centred on (0, 1, 0) in the Cornell box. A frame from a camera a
// third of a cell off the centre leaves it; one from 0.9 m along +x (1.8 cells) moves it one
// cell (truncated: the camera ends within a cell of the centre). The probe-state dump after it
// has the probes that stayed one plane lower in x than before, bit for bit (grid order from the
// new origin). Planted faults: the session not asking the field to track (origin stays); the
// dump in slot order (the stayed probes' states mismatch).
TEST_F(TrackingFieldTest, FieldFollowsTheCameraInWholeCells) {
  v1::CreateSessionRequest request = small_session_request("cornell_box", 1);
  ASSERT_EQ(request.field_params(0).name(), "counts");
  request.mutable_field_params(0)->set_value("4,4,4");
  add_params(
      request.mutable_field_params(),
      {{"spacing", "0.5,0.5,0.5"}, {"origin", "-0.75,0.25,-0.75"}, {"track_camera", "true"}});
  const v1::SessionInfo info = create_session(request);
  ASSERT_FALSE(info.session_id().empty());
  const std::string session = info.session_id();

  v1::Frame frame;
  const v1::Camera near_centre = look_at(0.15f, 1.0f, 0.1f, 0.15f, 1.0f, -1.0f);
  ASSERT_TRUE(render(session, 32, 32, &frame, &near_centre).ok());
  auto ctx = context();
  EXPECT_EQ(field_origin(*stub_, session, ctx.get()), glm::vec3(-0.75f, 0.25f, -0.75f));
  const std::vector<float> before = probe_state_texels(*stub_, session);

  const v1::Camera moved = look_at(0.9f, 1.0f, 0.0f, 0.9f, 1.0f, -1.0f);
  ASSERT_TRUE(render(session, 32, 32, &frame, &moved).ok());
  ctx = context();
  const glm::vec3 origin = field_origin(*stub_, session, ctx.get());
  std::printf("origin after the move: %g, %g, %g\n", origin.x, origin.y, origin.z);
  EXPECT_EQ(origin, glm::vec3(-0.25f, 0.25f, -0.75f));

  const std::vector<float> after = probe_state_texels(*stub_, session);
  ASSERT_EQ(before.size(), 64u * 4u);
  ASSERT_EQ(after.size(), before.size());
  uint32_t relocated = 0;
  for (uint32_t z = 0; z < 4; ++z) {
    for (uint32_t y = 0; y < 4; ++y) {
      for (uint32_t x = 0; x < 3; ++x) {
        const size_t now = (x + 4 * (y + 4 * z)) * 4, was = now + 4;
        for (size_t c = 0; c < 4; ++c) {
          EXPECT_EQ(after[now + c], before[was + c]) << "probe " << x << "," << y << "," << z;
        }
        relocated += before[was] != 0.0f || before[was + 1] != 0.0f ? 1 : 0;
      }
    }
  }
  EXPECT_GT(relocated, 0u);  // not a comparison of zeros: the floor layer was relocated
}

// A field of cascades over RPC: GetFieldParams lists its volumes (finest first, each twice as
// coarse, around one centre), frames render from the blend, and DumpAtlas dumps one volume at a
// time as a grid of its own: the two dumps together hold every probe of the field once (their
// states add up to the field's counts) and differ (the coarse volume's outer planes lie outside
// the box).
TEST_F(TrackingFieldTest, CascadesAreListedAndDumpedOneVolumeAtATime) {
  v1::CreateSessionRequest request = small_session_request("cornell_box", 1);
  ASSERT_EQ(request.field_params(0).name(), "counts");
  request.mutable_field_params(0)->set_value("4,4,4");
  add_params(request.mutable_field_params(),
             {{"spacing", "0.5,0.5,0.5"}, {"origin", "-0.75,0.25,-0.75"}, {"cascades", "2"}});
  const v1::SessionInfo info = create_session(request);
  ASSERT_FALSE(info.session_id().empty());
  ASSERT_EQ(info.field().volumes_size(), 2);
  const v1::FieldVolume& fine = info.field().volumes(0);
  const v1::FieldVolume& coarse = info.field().volumes(1);
  EXPECT_EQ(fine.spacing().x(), 0.5f);
  EXPECT_EQ(coarse.spacing().x(), 1.0f);
  EXPECT_EQ(coarse.counts_x(), 4);
  // Around one centre: (0, 1, 0).
  EXPECT_FLOAT_EQ(fine.origin().x() + 1.5f * fine.spacing().x(), 0.0f);
  EXPECT_FLOAT_EQ(coarse.origin().y() + 1.5f * coarse.spacing().y(), 1.0f);
  EXPECT_EQ(info.field().probes(), 128u);

  uint64_t states_in_dumps[4] = {0, 0, 0, 0};  // vigilant, awake, sleeping, off
  std::vector<float> state_texels[2], irradiance[2];
  for (uint32_t v = 0; v < 2; ++v) {
    SCOPED_TRACE("volume " + std::to_string(v));
    const v1::FieldVolume& volume = info.field().volumes(int(v));
    const AtlasDownload states = download_atlas(
        *stub_, info.session_id(), v1::ATLAS_KIND_PROBE_STATES, v1::ATLAS_FORMAT_RAW_F32, "", v);
    ASSERT_TRUE(states.status.ok()) << states.status.error_message();
    EXPECT_EQ(states.metadata.probe_counts_x(), volume.counts_x());
    EXPECT_EQ(states.metadata.probe_spacing().x(), volume.spacing().x());
    EXPECT_EQ(states.metadata.grid_origin().y(), volume.origin().y());
    state_texels[v] = raw_floats(states.bytes);
    ASSERT_EQ(state_texels[v].size(), 64u * 4u);
    for (size_t p = 0; p < 64; ++p) ++states_in_dumps[size_t(state_texels[v][p * 4 + 3]) & 3];
    const AtlasDownload atlas = download_atlas(*stub_, info.session_id(), v1::ATLAS_KIND_IRRADIANCE,
                                               v1::ATLAS_FORMAT_RAW_F32, "", v);
    ASSERT_TRUE(atlas.status.ok()) << atlas.status.error_message();
    // Exactly the rows of tiles 64 probes fill.
    const uint32_t side = atlas.metadata.texels_per_probe() + 2 * atlas.metadata.border_texels();
    const uint32_t per_row = atlas.metadata.tiles_per_row();
    EXPECT_EQ(atlas.metadata.height(), (64 + per_row - 1) / per_row * side);
    EXPECT_EQ(atlas.metadata.grid_origin().x(), volume.origin().x());
    irradiance[v] = raw_floats(atlas.bytes);
    double sum = 0.0;
    for (float t : irradiance[v]) sum += t;
    EXPECT_GT(sum, 0.0) << "volume " << v << " dumps a black atlas";
  }
  const v1::ProbeStateCounts& field = info.field().probe_states();
  std::printf("states in the two dumps: %llu vigilant, %llu awake, %llu sleeping, %llu off\n",
              static_cast<unsigned long long>(states_in_dumps[0]),
              static_cast<unsigned long long>(states_in_dumps[1]),
              static_cast<unsigned long long>(states_in_dumps[2]),
              static_cast<unsigned long long>(states_in_dumps[3]));
  EXPECT_EQ(states_in_dumps[0], field.vigilant());
  EXPECT_EQ(states_in_dumps[1], field.awake());
  EXPECT_EQ(states_in_dumps[2], field.sleeping());
  EXPECT_EQ(states_in_dumps[3], field.off());
  EXPECT_NE(state_texels[0], state_texels[1]);
  EXPECT_NE(irradiance[0], irradiance[1]);

  const AtlasDownload past = download_atlas(*stub_, info.session_id(), v1::ATLAS_KIND_IRRADIANCE,
                                            v1::ATLAS_FORMAT_RAW_F32, "", 2);
  EXPECT_EQ(past.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(past.status.error_message().find("volume 2: the field has 2 volume(s)"),
            std::string::npos)
      << past.status.error_message();
  v1::Frame frame;
  ASSERT_TRUE(render(info.session_id(), 32, 32, &frame).ok());
  EXPECT_GT(mean_level(decode(frame)), 5.0);
}

// QueryIrradiance of a field of cascades, per volume and blended, in the volumes of the test
// above: the fine volume (0.5 m, x in [-0.75, 0.75]) has weight 1 within a cell of its centre
// and 0 from its edge on, so at the centre the blend is the fine volume's answer and at
// x = 1.1 (past its grid, inside the coarse one) the coarse volume's; the two volumes answer
// differently at the centre. A volume past the field's is refused by name.
TEST_F(TrackingFieldTest, QueriesAnswerPerVolumeAndBlended) {
  v1::CreateSessionRequest request = small_session_request("cornell_box", 1);
  request.mutable_field_params(0)->set_value("4,4,4");
  add_params(request.mutable_field_params(),
             {{"spacing", "0.5,0.5,0.5"}, {"origin", "-0.75,0.25,-0.75"}, {"cascades", "2"}});
  const v1::SessionInfo info = create_session(request);
  ASSERT_FALSE(info.session_id().empty());
  auto ask = [&](std::optional<uint32_t> volume, v1::QueryIrradianceReply* reply) {
    v1::QueryIrradianceRequest query;
    query.set_session_id(info.session_id());
    for (const float x : {0.0f, 1.1f}) {
      v1::QueryPoint* point = query.add_points();
      point->mutable_position()->set_x(x);
      point->mutable_position()->set_y(1.0f);
      point->mutable_normal()->set_y(1.0f);
    }
    if (volume) query.set_volume(*volume);
    return stub_->QueryIrradiance(context().get(), query, reply);
  };
  v1::QueryIrradianceReply blend, fine, coarse, past;
  ASSERT_TRUE(ask(std::nullopt, &blend).ok());
  ASSERT_TRUE(ask(0u, &fine).ok());
  ASSERT_TRUE(ask(1u, &coarse).ok());
  auto red = [](const v1::QueryIrradianceReply& r, int i) { return r.irradiance(i).x(); };
  std::printf(
      "red at the centre: blend %.5f, fine %.5f, coarse %.5f; at x = 1.1: blend %.5f, "
      "coarse %.5f\n",
      red(blend, 0), red(fine, 0), red(coarse, 0), red(blend, 1), red(coarse, 1));
  EXPECT_GT(red(fine, 0), 0.01f);
  EXPECT_NEAR(red(blend, 0), red(fine, 0), 1e-5f);
  EXPECT_NEAR(red(blend, 1), red(coarse, 1), 1e-5f);
  EXPECT_GT(std::fabs(red(fine, 0) - red(coarse, 0)), 1e-3f);
  const grpc::Status refused = ask(2u, &past);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(refused.error_message().find("volume 2: the field has 2 volume(s)"), std::string::npos)
      << refused.error_message();
}

}  // namespace
}  // namespace ddgi::test
