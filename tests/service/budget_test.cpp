// The time budget over RPC (field parameter budget_ms; service/session_budget.h): a session
// created with a budget follows the configuration the calibration chose and reports it in
// FieldParams.budget; a second session on the same scene takes the cached calibration; an
// impossible budget, a malformed one and a budget without a field are refused by name and change
// nothing; parameters set by hand end the budget. The choice itself is tested with injected
// costs in tests/gpu/field_budget_test.cpp; here the costs are lavapipe's own.
#include <string>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

class BudgetTest : public ServiceTest {
 protected:
  // A calibration lavapipe runs in seconds: a 64x64 frame, a 128-spp reference.
  void configure(service::ServerOptions& options) override {
    options.budget_calibration.width = options.budget_calibration.height = 64;
    options.budget_calibration.reference_spp = 128;
    options.budget_calibration.warmup_updates = 8;
    options.budget_calibration.timed_frames = 2;
  }

  v1::CreateSessionRequest budget_request(const char* budget_ms) const {
    v1::CreateSessionRequest request = small_session_request("cornell_box", 2);
    request.mutable_field_params(0)->set_value("3,3,3");  // counts: a coarser grid exists
    add_params(request.mutable_field_params(), {{"budget_ms", budget_ms}});
    return request;
  }
};

TEST_F(BudgetTest, SessionFollowsTheChoiceReportsItAndTheCalibrationIsCached) {
  const v1::SessionInfo info = create_session(budget_request("1e6"));
  ASSERT_FALSE(info.session_id().empty());
  ASSERT_TRUE(info.field().has_budget());
  const v1::FieldBudget& budget = info.field().budget();
  // Cornell box: a point light, no emissive surface -> rays 32..256 x {3x3x3, 2x2x2}.
  EXPECT_EQ(budget.candidates(), 8u);
  EXPECT_FALSE(budget.from_cache());
  EXPECT_EQ(budget.budget_ms(), 1e6);
  EXPECT_EQ(budget.width(), 64u);
  EXPECT_GT(budget.cost_ms(), 0.0);
  EXPECT_NEAR(budget.cost_ms(), budget.field_ms() + budget.frame_ms(), 1e-9);
  EXPECT_GT(budget.flip(), 0.0);
  EXPECT_LT(budget.flip(), 0.7);  // a 3x3x3 field in the box: 0.58-0.62 measured at 64x64
  EXPECT_GT(budget.mean_ratio(), 0.5);
  // The field is what the budget chose: its rays, and its grid.
  ASSERT_GE(budget.params_size(), 1);
  EXPECT_EQ(budget.params(0).name(), "rays_per_probe");
  EXPECT_EQ(param_value(info.field(), "rays_per_probe"), budget.params(0).value());
  const bool coarse = budget.configuration().find("coarse") != std::string::npos;
  EXPECT_EQ(info.field().probes(), coarse ? 8u : 27u) << budget.configuration();

  const v1::SessionInfo again = create_session(budget_request("1e6"));
  ASSERT_TRUE(again.field().has_budget());
  EXPECT_TRUE(again.field().budget().from_cache());
  EXPECT_EQ(again.field().budget().configuration(), budget.configuration());
  EXPECT_EQ(again.field().budget().flip(), budget.flip());
}

TEST_F(BudgetTest, RefusalsNameTheProblemAndChangeNothing) {
  const v1::SessionInfo info = create_session(budget_request("1e6"));
  ASSERT_TRUE(info.field().has_budget());
  const std::string session = info.session_id();
  v1::FieldParams reply;

  // A new budget starts from the session's own parameters, not the last choice: the same
  // calibration (cached), another choice within it.
  grpc::Status status = set_field_param(session, "budget_ms", "1e6", &reply);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_TRUE(reply.has_budget());
  EXPECT_TRUE(reply.budget().from_cache());
  EXPECT_EQ(reply.budget().configuration(), info.field().budget().configuration());

  status = set_field_param(session, "budget_ms", "1e-9", &reply);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(status.error_message().find("budget_ms 1e-09 cannot be met: the cheapest "
                                        "configuration measured for this scene"),
            std::string::npos)
      << status.error_message();
  status = set_field_param(session, "budget_ms", "fast", &reply);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("budget_ms 'fast' is not a number"), std::string::npos)
      << status.error_message();
  status = set_field_param(session, "budget_ms", "-2", &reply);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("budget_ms must be in (0, 1e+06]"), std::string::npos)
      << status.error_message();

  v1::GetFieldParamsRequest get;
  get.set_session_id(session);
  v1::FieldParams now;
  ASSERT_TRUE(stub_->GetFieldParams(context().get(), get, &now).ok());
  ASSERT_TRUE(now.has_budget());
  EXPECT_EQ(now.budget().configuration(), info.field().budget().configuration());
  EXPECT_EQ(param_value(now, "rays_per_probe"), param_value(info.field(), "rays_per_probe"));

  // Ended (budget_ms 0): the report goes, the field stays as it is (not restarted: its update
  // count goes on); set by hand likewise, but restarted as any parameter change is.
  ASSERT_GT(now.updates(), 0u);
  ASSERT_TRUE(set_field_param(session, "budget_ms", "0", &reply).ok());
  EXPECT_FALSE(reply.has_budget());
  EXPECT_EQ(param_value(reply, "rays_per_probe"), param_value(info.field(), "rays_per_probe"));
  EXPECT_GE(reply.updates(), now.updates());
  ASSERT_TRUE(set_field_param(session, "budget_ms", "1e6", &reply).ok());
  ASSERT_TRUE(reply.has_budget());
  ASSERT_TRUE(set_field_param(session, "hysteresis", "0.9", &reply).ok());
  EXPECT_FALSE(reply.has_budget());
  EXPECT_EQ(param_value(reply, "rays_per_probe"), param_value(info.field(), "rays_per_probe"));

  v1::CreateSessionRequest no_field = budget_request("4");
  no_field.set_gi(false);
  v1::SessionInfo refused;
  status = stub_->CreateSession(context().get(), no_field, &refused);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(status.error_message().find("budget_ms chooses the irradiance field's"),
            std::string::npos)
      << status.error_message();
}

}  // namespace
}  // namespace ddgi::test
