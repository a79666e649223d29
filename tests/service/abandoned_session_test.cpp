// A CreateSession whose client has gone (deadline passed, or cancelled) before the session was
// ready: nobody will ever learn its id, so the server closes it instead of leaving an orphan
// that holds a session slot and GPU memory.
//
// The session is held "not ready" by the server's test-only loaded hook (ServerOptions::
// test_session_loaded_hook) until the test releases it, so the client is gone before the session
// is ready however fast the device loads the scene.
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

// Holds new sessions in the server's loaded hook while held; counts the sessions that reached it.
class LoadGate {
 public:
  void hold() {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = true;
  }
  void release() {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = false;
    changed_.notify_all();
  }
  // The hook: waits while held, bounded so a failing test cannot hang the server's shutdown.
  void pass() {
    std::unique_lock<std::mutex> lock(mutex_);
    ++entered_;
    changed_.notify_all();
    changed_.wait_for(lock, std::chrono::seconds(60), [&] { return !held_; });
  }
  // Waits (bounded) until `count` sessions reached the hook.
  bool wait_entered(int count) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(60), [&] { return entered_ >= count; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool held_ = false;
  int entered_ = 0;
};

class AbandonedSessionTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override {
    options.test_session_loaded_hook = [gate = gate_](const std::string&) { gate->pass(); };
  }
  std::shared_ptr<LoadGate> gate_ = std::make_shared<LoadGate>();
};

// The server learns that a client went away through its own copy of the call's state, a moment
// after the client does; the session is released only after this.
constexpr auto kServerNotices = std::chrono::milliseconds(200);

TEST_F(AbandonedSessionTest, ClientGoneBeforeSessionReadyLeavesNoSession) {
  const v1::CreateSessionRequest request = small_session_request("cornell_box", 2);
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

  // A deadline long enough for the request to reach the server on a loaded machine; with the
  // gate held no answer can come before it.
  gate_->hold();
  {
    v1::SessionInfo info;
    auto ctx = context(1.0);
    const grpc::Status status = stub_->CreateSession(ctx.get(), request, &info);
    ASSERT_EQ(status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED) << status.error_message();
  }
  ASSERT_TRUE(gate_->wait_entered(1)) << "the server never finished loading the session";
  EXPECT_EQ(server().metrics().sessions_created.load(), 1u);
  std::this_thread::sleep_for(kServerNotices);
  gate_->release();
  EXPECT_TRUE(no_session_left()) << "the abandoned session stayed open";

  // The same for a client that cancels while its session waits at the gate.
  gate_->hold();
  {
    v1::SessionInfo info;
    auto ctx = context();
    std::thread cancel([&] {
      if (gate_->wait_entered(2)) ctx->TryCancel();
    });
    const grpc::Status status = stub_->CreateSession(ctx.get(), request, &info);
    cancel.join();
    ASSERT_EQ(status.error_code(), grpc::StatusCode::CANCELLED) << status.error_message();
  }
  EXPECT_EQ(server().metrics().sessions_created.load(), 2u);
  std::this_thread::sleep_for(kServerNotices);
  gate_->release();
  EXPECT_TRUE(no_session_left()) << "the cancelled client's session stayed open";

  // A client that waits still gets its session (the gate open), and it stays.
  const std::string kept = create_session();
  EXPECT_FALSE(kept.empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(list_size(), 1);
}

}  // namespace
}  // namespace ddgi::test
