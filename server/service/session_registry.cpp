#include "service/session_registry.h"

#include <random>

#include "core/log.h"
#include "service/process_memory.h"
#include "service/text.h"

namespace ddgi::service {

SessionRegistry::SessionRegistry(SessionEnv env, SessionLoadedHook loaded_hook)
    : env_(std::move(env)), loaded_hook_(std::move(loaded_hook)) {}

SessionRegistry::~SessionRegistry() {
  close_all();
}

std::string SessionRegistry::new_id() {
  // Ids are capabilities of a sort (without auth, knowing one lets you drive the session):
  // 64 random bits, not a counter.
  static thread_local std::mt19937_64 generator{std::random_device{}()};
  char text[24];
  std::snprintf(text, sizeof(text), "s%016llx", static_cast<unsigned long long>(generator()));
  return text;
}

Status SessionRegistry::create(SessionOptions options, SceneRequest scene, v1::SessionInfo* reply,
                               const Completion& done) {
  std::string id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return unavailable(closed_message_);
    if (sessions_.size() >= env_.limits->max_sessions) {
      return resource_exhausted("the server already has " + std::to_string(sessions_.size()) +
                                " sessions, the most allowed (--max-sessions " +
                                std::to_string(env_.limits->max_sessions) + "); close one first");
    }
    do {
      id = new_id();
    } while (sessions_.count(id));
    sessions_[id] = nullptr;  // holds the slot while the session is made
  }
  SessionEnv env = env_;
  auto tracker = loops_;
  {
    std::lock_guard<std::mutex> lock(tracker->mutex);
    ++tracker->live;
  }
  env.metrics->sessions.fetch_add(1);
  env.metrics->sessions_created.fetch_add(1);
  env.on_loop_exit = [tracker] {
    // The session's scene, fields and frame buffers are freed by now; without this, their
    // memory would stay resident in the loop thread's malloc arena.
    release_free_memory();
    std::lock_guard<std::mutex> lock(tracker->mutex);
    --tracker->live;
    tracker->done.notify_all();
  };
  const std::string label = scene.label;
  Completion finish = [this, id, label, done](const Status& status) {
    if (loaded_hook_) loaded_hook_(label);
    if (!status.ok()) {
      LOG_INFO << "session failed to load session=" << id << ": " << status.error().message;
      (void)close(id, nullptr);
    }
    done(status);
  };
  std::shared_ptr<Session> session = Session::create(id, std::move(env), std::move(options));
  bool closing;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing = closed_;
    if (!closing) sessions_[id] = session;  // before the loop runs, so a failed load finds it
  }
  session->start(std::move(scene), reply, std::move(finish));
  if (closing) session->stop(nullptr);  // shutdown began meanwhile: the load fails UNAVAILABLE
  LOG_INFO << "session created session=" << id << " scene=" << label;
  return ok_status();
}

Result<std::shared_ptr<Session>> SessionRegistry::find(const std::string& session_id) const {
  if (session_id.empty()) return invalid_argument("session_id is empty");
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = sessions_.find(session_id);
  if (it == sessions_.end() || it->second == nullptr) {
    return not_found("no session " + printable(session_id) + " (closed, or never created)");
  }
  return it->second;
}

Status SessionRegistry::close(const std::string& session_id, std::function<void()> on_closed) {
  if (session_id.empty()) return invalid_argument("session_id is empty");
  std::shared_ptr<Session> session;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = sessions_.find(session_id);
    if (it == sessions_.end()) {
      return not_found("no session " + printable(session_id) + " (closed, or never created)");
    }
    session = std::move(it->second);
    sessions_.erase(it);
  }
  if (session) {
    session->stop(std::move(on_closed));
  } else if (on_closed) {
    on_closed();  // (cannot happen for callers outside create: the slot is filled at once)
  }
  return ok_status();
}

std::vector<v1::SessionSummary> SessionRegistry::list() const {
  std::vector<v1::SessionSummary> out;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, session] : sessions_) {
    if (session) out.push_back(session->summary());
  }
  return out;
}

size_t SessionRegistry::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sessions_.size();
}

void SessionRegistry::close_all(std::optional<Error> reason) {
  std::map<std::string, std::shared_ptr<Session>> sessions;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (reason && !closed_) closed_message_ = reason->message;
    closed_ = true;
    sessions.swap(sessions_);
  }
  for (auto& [id, session] : sessions) {
    if (session) session->stop(nullptr, reason);
  }
}

bool SessionRegistry::wait_for_loops(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(loops_->mutex);
  return loops_->done.wait_for(lock, timeout, [&] { return loops_->live == 0; });
}

}  // namespace ddgi::service
