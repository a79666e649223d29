// A session's configuration over RPC (service/session_scene.h, service/calibrator.h): a session
// streams at once with the static default while its scene is calibrated in the background, then
// switches to the rule's choice and reports it (FieldParams.budget) and the calibration's progress
// (FieldParams.calibration); a second session takes the cached calibration at load, and so does
// a restarted server on the same cache folder; a budget nothing fits is served with the cheapest
// configuration and says by how much it misses; malformed budgets and a budget without a field are
// refused by name; parameters set by hand leave the choice until budget_ms is set again; a server
// that does not calibrate says why. The rule on hand-made tables:
// tests/unit/tools/field_choice_test.cpp; the choice's light: tests/gpu/session_choice_test.cpp.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

using State = v1::FieldCalibration;

// The five gatherings (rays, grid and paths per pixel fixed by the request), with an H100's
// 1080p costs: the static default and the bias 1.4 ms, one bounce 3.4 ms.
const std::vector<double> kInjectedMs = {1.4, 1.4, 3.4, 3.4, 3.4};

std::string cache_dir() {
  return (std::filesystem::temp_directory_path() /
          ("ddgi-calibrations-" + std::to_string(::getpid())))
      .string();
}

void configure_calibration(service::ServerOptions& options) {
  options.calibration = true;
  options.budget_cache_dir = cache_dir();
  // A calibration lavapipe runs in seconds: a 48x48 scored frame, a 64-spp reference.
  options.budget_calibration.width = options.budget_calibration.height = 48;
  options.budget_calibration.reference_spp = 64;
  options.budget_calibration.warmup_updates = 8;
  options.budget_calibration.scored_frames = 2;
  options.budget_calibration.injected_ms = kInjectedMs;
}

class CalibrationTest : public ServiceTest {
 protected:
  void SetUp() override {
    std::filesystem::remove_all(cache_dir());
    ServiceTest::SetUp();
  }
  void TearDown() override {
    ServiceTest::TearDown();
    std::filesystem::remove_all(cache_dir());
  }
  void configure(service::ServerOptions& options) override { configure_calibration(options); }

  v1::CreateSessionRequest request(const char* budget_ms = nullptr) const {
    v1::CreateSessionRequest r = small_session_request("cornell_box", 2);
    add_params(r.mutable_field_params(), {{"pixel_paths", "0"}});
    if (budget_ms) add_params(r.mutable_field_params(), {{"budget_ms", budget_ms}});
    return r;
  }

  // GetSession until the calibration is done (or failed), at most 180 s.
  static v1::SessionInfo wait_for_calibration(v1::RenderService::Stub& stub,
                                              const std::string& session) {
    v1::GetSessionRequest get;
    get.set_session_id(session);
    v1::SessionInfo info;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(180);
    while (std::chrono::steady_clock::now() < deadline) {
      grpc::ClientContext context;
      info.Clear();
      EXPECT_TRUE(stub.GetSession(&context, get, &info).ok());
      const State::State state = info.field().calibration().state();
      if (state == State::STATE_DONE || state == State::STATE_FAILED) return info;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ADD_FAILURE() << "the calibration did not finish in 180 s";
    return info;
  }
};

TEST_F(CalibrationTest, StreamsAtOnceThenSwitchesAndTheNextSessionsTakeTheCache) {
  const v1::SessionInfo info = create_session(request());
  ASSERT_FALSE(info.session_id().empty());
  // No wait at load: the static default, the calibration queued or running, no choice yet.
  const v1::FieldCalibration& started = info.field().calibration();
  EXPECT_TRUE(started.state() == State::STATE_QUEUED || started.state() == State::STATE_RUNNING)
      << State::State_Name(started.state());
  EXPECT_EQ(started.candidates(), 5u);
  EXPECT_EQ(started.budget_ms(), 4.0) << "the server's default budget";
  EXPECT_FALSE(info.field().has_budget());
  EXPECT_EQ(param_value(info.field(), "probe_bounces"), "0");
  v1::Frame frame;  // frames come meanwhile
  ASSERT_TRUE(render(info.session_id(), 32, 32, &frame).ok());

  const v1::SessionInfo done = wait_for_calibration(*stub_, info.session_id());
  const v1::FieldCalibration& calibration = done.field().calibration();
  ASSERT_EQ(calibration.state(), State::STATE_DONE) << calibration.message();
  EXPECT_TRUE(calibration.switched());
  EXPECT_FALSE(calibration.from_cache());
  EXPECT_EQ(calibration.candidates_done(), 5u);
  EXPECT_GT(calibration.seconds(), 0.0);  // from the load to the switch
  ASSERT_TRUE(done.field().has_budget());
  const v1::FieldBudget& budget = done.field().budget();
  EXPECT_EQ(budget.budget_ms(), 4.0);
  EXPECT_TRUE(budget.budget_met());
  EXPECT_LE(budget.cost_ms(), 4.0);
  EXPECT_NEAR(budget.cost_ms(), budget.shadow_ms() + budget.field_ms() + budget.frame_ms(), 1e-9);
  EXPECT_GT(budget.flip(), 0.0);
  EXPECT_GT(budget.flip_noise(), 0.0);
  EXPECT_GT(budget.mean_ratio(), 0.3);
  EXPECT_EQ(budget.candidates(), 5u);
  // The field is what the rule chose.
  for (const v1::FieldParam& p : budget.params()) {
    EXPECT_EQ(param_value(done.field(), p.name()), p.value()) << budget.configuration();
  }
  EXPECT_EQ(param_value(done.field(), "rays_per_probe"), "16") << "fixed by the request";
  ASSERT_TRUE(render(info.session_id(), 32, 32, &frame).ok());

  // A second session: the cached calibration at load, no switch.
  const v1::SessionInfo again = create_session(request());
  EXPECT_EQ(again.field().calibration().state(), State::STATE_DONE);
  EXPECT_TRUE(again.field().calibration().from_cache());
  ASSERT_TRUE(again.field().has_budget());
  EXPECT_EQ(again.field().budget().configuration(), budget.configuration());
  EXPECT_EQ(again.field().budget().flip(), budget.flip());

  // A restarted server on the same cache folder: no calibration either.
  service::ServerOptions options = test_server_options();
  configure_calibration(options);
  auto restarted = service::Server::start(service_context(), options);
  ASSERT_TRUE(restarted.ok()) << restarted.error().message;
  auto stub = v1::RenderService::NewStub(grpc::CreateChannel(
      "127.0.0.1:" + std::to_string((*restarted)->port()), grpc::InsecureChannelCredentials()));
  grpc::ClientContext create_context;
  v1::SessionInfo fresh;
  ASSERT_TRUE(stub->CreateSession(&create_context, request(), &fresh).ok());
  EXPECT_EQ(fresh.field().calibration().state(), State::STATE_DONE);
  EXPECT_TRUE(fresh.field().calibration().from_cache());
  EXPECT_EQ(fresh.field().budget().configuration(), budget.configuration());
  EXPECT_TRUE((*restarted)->shutdown());
}

TEST_F(CalibrationTest, EveryBudgetIsServedRefusalsNameTheProblem) {
  const v1::SessionInfo info = create_session(request("2"));
  const std::string session = info.session_id();
  EXPECT_EQ(info.field().calibration().budget_ms(), 2.0);
  const v1::SessionInfo done = wait_for_calibration(*stub_, session);
  ASSERT_TRUE(done.field().has_budget());
  // 2 ms: the static default or the bias (1.4 ms), not a bounce (3.4 ms).
  EXPECT_EQ(done.field().budget().cost_ms(), 1.4);
  EXPECT_EQ(param_value(done.field(), "probe_bounces"), "0");

  // Below everything: served with the cheapest, saying by how much it misses.
  v1::FieldParams reply;
  grpc::Status status = set_field_param(session, "budget_ms", "0.5", &reply);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_TRUE(reply.has_budget());
  EXPECT_FALSE(reply.budget().budget_met());
  EXPECT_NEAR(reply.budget().over_ms(), 0.9, 1e-9);
  EXPECT_NE(reply.budget().note().find("budget not met by 0.90 ms"), std::string::npos)
      << reply.budget().note();
  // Room for a bounce: 8 ms chooses among all five.
  ASSERT_TRUE(set_field_param(session, "budget_ms", "8", &reply).ok());
  EXPECT_TRUE(reply.budget().budget_met());
  EXPECT_EQ(reply.calibration().budget_ms(), 8.0);
  // 0: back to the server's default.
  ASSERT_TRUE(set_field_param(session, "budget_ms", "0", &reply).ok());
  EXPECT_EQ(reply.budget().budget_ms(), 4.0);

  status = set_field_param(session, "budget_ms", "fast", &reply);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("budget_ms 'fast' is not a number"), std::string::npos)
      << status.error_message();
  status = set_field_param(session, "budget_ms", "-2", &reply);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("budget_ms must be in (0, 1e+06]"), std::string::npos)
      << status.error_message();

  // Set by hand: the field leaves the choice; budget_ms follows it again.
  ASSERT_TRUE(set_field_param(session, "hysteresis", "0.9", &reply).ok());
  EXPECT_FALSE(reply.has_budget());
  EXPECT_NE(reply.calibration().message().find("set by hand"), std::string::npos);
  ASSERT_TRUE(set_field_param(session, "budget_ms", "4", &reply).ok());
  EXPECT_TRUE(reply.has_budget());

  v1::CreateSessionRequest no_field = request("4");
  no_field.set_gi(false);
  v1::SessionInfo refused;
  status = stub_->CreateSession(context().get(), no_field, &refused);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(status.error_message().find("budget_ms chooses the irradiance field's"),
            std::string::npos)
      << status.error_message();
}

// A server that calibrates nothing (ServerOptions' default, and ddgi-server's on a CPU device):
// the static default, and the reason in the report.
class NoCalibrationTest : public ServiceTest {};

TEST_F(NoCalibrationTest, TheSessionSaysWhy) {
  const v1::SessionInfo info = create_session(small_session_request("cornell_box", 2));
  EXPECT_EQ(info.field().calibration().state(), State::STATE_OFF);
  EXPECT_NE(info.field().calibration().message().find("--calibration off"), std::string::npos)
      << info.field().calibration().message();
  EXPECT_FALSE(info.field().has_budget());
}

}  // namespace
}  // namespace ddgi::test
