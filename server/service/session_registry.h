// All sessions of the server, by id. Enforces max_sessions, hands out unguessable ids, and
// tracks the frame loops so shutdown can wait for them (bounded) before the GPU goes away.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "service/session.h"

namespace ddgi::service {

class SessionRegistry {
 public:
  // Test-only: runs on a new session's loop thread once its scene load ended (with the scene's
  // label), before CreateSession is answered. A test that blocks in it holds the session in the
  // "not ready" state for as long as it needs, instead of counting on a slow load
  // (tests/service/abandoned_session_test.cpp). Production servers leave it empty.
  using SessionLoadedHook = std::function<void(const std::string& scene_label)>;

  explicit SessionRegistry(SessionEnv env, SessionLoadedHook loaded_hook = {});
  ~SessionRegistry();

  // Starts a session; RESOURCE_EXHAUSTED beyond max_sessions. `done` runs once the scene is
  // loaded; when loading fails the session is closed again before `done` sees the error.
  // On error `done` is not called (and not consumed): the caller answers.
  Status create(SessionOptions options, SceneRequest scene, v1::SessionInfo* reply,
                const Completion& done);
  // INVALID_ARGUMENT for an empty id, NOT_FOUND for an unknown one.
  Result<std::shared_ptr<Session>> find(const std::string& session_id) const;
  // Removes the session; `on_closed` runs once its GPU memory is freed.
  Status close(const std::string& session_id, std::function<void()> on_closed);
  std::vector<v1::SessionSummary> list() const;
  size_t size() const;

  // Closes every session and refuses new ones: "the server is shutting down", or `reason`
  // (a lost device), which then also ends the sessions' streams and queued commands.
  void close_all(std::optional<Error> reason = std::nullopt);
  // True when every frame loop ended within `timeout`.
  bool wait_for_loops(std::chrono::milliseconds timeout);

 private:
  struct LoopTracker {
    std::mutex mutex;
    std::condition_variable done;
    int live = 0;
  };
  std::string new_id();

  SessionEnv env_;
  SessionLoadedHook loaded_hook_;
  std::shared_ptr<LoopTracker> loops_ = std::make_shared<LoopTracker>();
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  bool closed_ = false;
  std::string closed_message_ = "the server is shutting down";  // what create() answers then
};

}  // namespace ddgi::service
