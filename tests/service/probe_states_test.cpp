// The irradiance field's probe-state counts over RPC: GetFieldParams (and SessionInfo.field)
// carry them; they sum to the probe count, agree with the states in the probe-state atlas, and
// a probe placed in the middle of a solid cube, too deep for relocation to move it out, counts
// as off.
#include <array>
#include <vector>

#include "tests/service/atlas_download.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

using ProbeStatesTest = ServiceTest;

TEST_F(ProbeStatesTest, CountsOverRpcMatchTheField) {
  // box_on_floor: a 1 m cube on [-0.5, 0.5] x [0, 1] x [-0.5, 0.5]. A line of probes 0.6 m
  // apart from its centre: the first is 0.5 m from every face, relocation may move it only
  // 0.45 x 0.6 = 0.27 m (probe_offset_limit), so it stays inside; the others are outside.
  v1::CreateSessionRequest request = small_session_request("box_on_floor", 1);
  ASSERT_EQ(request.field_params(0).name(), "counts");
  request.mutable_field_params(0)->set_value("4,1,1");
  add_params(request.mutable_field_params(), {{"origin", "0,0.5,0"}, {"spacing", "0.6,0.6,0.6"}});
  const v1::SessionInfo info = create_session(request);
  ASSERT_FALSE(info.session_id().empty());

  v1::GetFieldParamsRequest get;
  get.set_session_id(info.session_id());
  v1::FieldParams params;
  auto ctx = context();
  ASSERT_TRUE(stub_->GetFieldParams(ctx.get(), get, &params).ok());
  ASSERT_TRUE(params.has_probe_states());
  const v1::ProbeStateCounts& counts = params.probe_states();
  std::printf("probe states: %llu vigilant, %llu awake, %llu sleeping, %llu off of %llu\n",
              static_cast<unsigned long long>(counts.vigilant()),
              static_cast<unsigned long long>(counts.awake()),
              static_cast<unsigned long long>(counts.sleeping()),
              static_cast<unsigned long long>(counts.off()),
              static_cast<unsigned long long>(params.probes()));
  EXPECT_EQ(params.probes(), 4u);
  EXPECT_EQ(counts.vigilant() + counts.awake() + counts.sleeping() + counts.off(), params.probes());
  EXPECT_GE(counts.off(), 1u) << "the probe inside the cube is not off";
  EXPECT_LT(counts.off(), 4u) << "probes outside the cube are off too";

  // SessionInfo carries the same counts.
  ASSERT_TRUE(info.has_field());
  EXPECT_EQ(info.field().probe_states().SerializeAsString(), counts.SerializeAsString());

  // The GPU's per-probe states (the probe-state atlas) give the same counts, and probe 0 (in
  // the cube's centre) is the off one.
  const AtlasDownload dump = download_atlas(*stub_, info.session_id(), v1::ATLAS_KIND_PROBE_STATES,
                                            v1::ATLAS_FORMAT_RAW_F32);
  ASSERT_TRUE(dump.status.ok()) << dump.status.error_message();
  const std::vector<float> texels = raw_floats(dump.bytes);
  ASSERT_EQ(texels.size(), 4u * 4u);
  std::array<uint64_t, 4> seen{};
  for (size_t probe = 0; probe < 4; ++probe) {
    const float state = texels[probe * 4 + 3];
    ASSERT_TRUE(state == 0.0f || state == 1.0f || state == 2.0f || state == 3.0f) << state;
    ++seen[size_t(state)];
  }
  EXPECT_EQ(seen[0], counts.vigilant());
  EXPECT_EQ(seen[1], counts.awake());
  EXPECT_EQ(seen[2], counts.sleeping());
  EXPECT_EQ(seen[3], counts.off());
  EXPECT_EQ(texels[3], 3.0f) << "probe 0 sits in the cube's centre";

  // The shadow field has no probe states: absent there.
  get.set_field(v1::FIELD_KIND_SHADOW);
  ctx = context();
  EXPECT_EQ(stub_->GetFieldParams(ctx.get(), get, &params).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
}

}  // namespace
}  // namespace ddgi::test
