// The energy calibration over RPC (ServerOptions::energy_calibration; tools/field_energy.h): a
// session that sets none of its parameters gets the choice applied to its field and reported in
// FieldParams.energy, a second session on the scene takes the cached calibration, a session that
// sets one of them keeps its own (nothing reported), and setting one by hand ends the report.
// Whether the choice keeps the light: tests/gpu/field_energy_test.cpp.
#include <string>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

class EnergyTest : public ServiceTest {
 protected:
  // A calibration lavapipe runs in seconds: a 48x48 frame, a 64-spp reference.
  void configure(service::ServerOptions& options) override {
    options.energy_calibration = true;
    options.energy_options.width = options.energy_options.height = 48;
    options.energy_options.reference_spp = 64;
    options.energy_options.warmup_updates = 8;
    options.energy_options.timed_frames = 1;
  }
};

TEST_F(EnergyTest, SessionsGetTheChoiceUnlessTheySetItsParameters) {
  const v1::SessionInfo info = create_session(small_session_request("cornell_box", 2));
  ASSERT_FALSE(info.session_id().empty());
  ASSERT_TRUE(info.field().has_energy());
  const v1::FieldEnergy& energy = info.field().energy();
  EXPECT_EQ(energy.candidates(), 6u);
  EXPECT_FALSE(energy.from_cache());
  // Measured, not made up: the box is lit in both views; a 2x2x2 field 8 updates in is far from
  // settled (lavapipe, 48x48: static default 0.635 / 0.089, 'paths 1, gamma 1' 0.695 / 0.238).
  EXPECT_GT(energy.mean_ratio(), 0.5);
  EXPECT_GT(energy.indirect_ratio(), 0.02);
  EXPECT_GT(energy.default_indirect_ratio(), 0.02);
  if (energy.configuration() != "static default") {
    EXPECT_NE(energy.indirect_ratio(), energy.default_indirect_ratio());
  }
  EXPECT_GT(energy.flip(), 0.0);
  EXPECT_GT(energy.calibration_seconds(), 0.0);
  // The field has the chosen settings; the static default sets nothing.
  for (const v1::FieldParam& p : energy.params()) {
    EXPECT_EQ(param_value(info.field(), p.name()), p.value()) << energy.configuration();
  }
  EXPECT_EQ(energy.params_size() == 0, energy.configuration() == "static default");

  const v1::SessionInfo again = create_session(small_session_request("cornell_box", 2));
  ASSERT_TRUE(again.field().has_energy());
  EXPECT_TRUE(again.field().energy().from_cache());
  EXPECT_EQ(again.field().energy().configuration(), energy.configuration());
  EXPECT_EQ(again.field().energy().indirect_ratio(), energy.indirect_ratio());

  // Set by the session: its own value, no calibration.
  v1::CreateSessionRequest own = small_session_request("cornell_box", 2);
  add_params(own.mutable_field_params(), {{"self_shadow_bias", "0.25"}});
  const v1::SessionInfo kept = create_session(own);
  ASSERT_FALSE(kept.session_id().empty());
  EXPECT_FALSE(kept.field().has_energy());
  EXPECT_EQ(param_value(kept.field(), "self_shadow_bias"), "0.25");

  // Another parameter set by hand keeps the report; one of the calibration's ends it.
  v1::FieldParams reply;
  ASSERT_TRUE(set_field_param(info.session_id(), "hysteresis", "0.9", &reply).ok());
  EXPECT_TRUE(reply.has_energy());
  ASSERT_TRUE(set_field_param(info.session_id(), "irradiance_gamma", "2", &reply).ok());
  EXPECT_FALSE(reply.has_energy());
  EXPECT_EQ(param_value(reply, "irradiance_gamma"), "2");
}

}  // namespace
}  // namespace ddgi::test
