// A CreateSession whose client has gone (deadline passed, or cancelled) before the session was
// ready: nobody will ever learn its id, so the server closes it instead of leaving an orphan
// that holds a session slot and GPU memory.
#include <thread>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

using AbandonedSessionTest = ServiceTest;

TEST_F(AbandonedSessionTest, ClientGoneBeforeSessionReadyLeavesNoSession) {
  // Slow enough to load (100 warm-up updates of 64 probes) that a 100 ms deadline passes first.
  v1::CreateSessionRequest request = small_session_request("cornell_box", 100);
  request.mutable_field_params(0)->set_value("4,4,4");
  auto list_size = [&] {
    v1::ListSessionsReply list;
    auto ctx = context();
    EXPECT_TRUE(stub_->ListSessions(ctx.get(), {}, &list).ok());
    return list.sessions_size();
  };
  // Waits (bounded) until the server holds no session; false when one stays.
  auto no_session_left = [&] {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < end) {
      if (list_size() == 0 && server().metrics().sessions.load() == 0) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  };

  {
    v1::SessionInfo info;
    auto ctx = context(0.1);
    const grpc::Status status = stub_->CreateSession(ctx.get(), request, &info);
    ASSERT_EQ(status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED) << status.error_message();
  }
  EXPECT_EQ(server().metrics().sessions_created.load(), 1u)
      << "the server never started making the session: nothing was tested";
  EXPECT_TRUE(no_session_left()) << "the abandoned session stayed open";

  // The same for a client that cancels.
  {
    v1::SessionInfo info;
    auto ctx = context();
    std::thread cancel([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      ctx->TryCancel();
    });
    const grpc::Status status = stub_->CreateSession(ctx.get(), request, &info);
    cancel.join();
    ASSERT_EQ(status.error_code(), grpc::StatusCode::CANCELLED) << status.error_message();
  }
  EXPECT_EQ(server().metrics().sessions_created.load(), 2u);
  EXPECT_TRUE(no_session_left()) << "the cancelled client's session stayed open";

  // A client that waits still gets its session, and it stays.
  const std::string kept = create_session();
  EXPECT_FALSE(kept.empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(list_size(), 1);
}

}  // namespace
}  // namespace ddgi::test
