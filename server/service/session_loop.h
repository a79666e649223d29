// The engine of a session, apart from what the session holds: a command queue that one thread
// runs in arrival order, the sequence numbers that say which command a frame already shows,
// frame pacing (at most --max-fps frames a second, none while nobody waits for one, none before
// the owner's frames in flight are nearly done) and the order of teardown. Frames are pipelined: an
// iteration's frames are read back during the next iteration, after its frames were submitted, or
// before the loop sleeps (finish_frames), so a paced or idle loop still delivers each frame as soon
// as the GPU is done with it. It knows nothing of scenes, views or the wire: its owner says whether
// a frame is wanted, produces it, and frees its state when the loop ends.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi::service {

// Finishes one RPC; called exactly once, from the loop thread or an encoder thread.
using Completion = std::function<void(const Status&)>;

int64_t unix_micros();

// A command as frames report it: its sequence number and when it arrived.
struct CommandStamp {
  uint64_t seq = 0;
  int64_t arrival_unix_us = 0;
};

class SessionLoop {
 public:
  // What the loop calls, always on its own thread.
  class Owner {
   public:
    virtual ~Owner() = default;
    // Whether someone waits for a frame (a stream or a one-shot request). Called under the
    // loop's lock: it must not call back into the loop.
    virtual bool wants_frame() = 0;
    // Starts one frame (and may finish the previous one); `index` counts the loop's frames from
    // 1, `last_applied` is the newest state-changing command applied before it.
    virtual void produce_frame(uint64_t index, const CommandStamp& last_applied) = 0;
    // The loop is about to sleep (no frame due): finish every frame still in flight.
    virtual void finish_frames() = 0;
    // The earliest time to start the next frame, however soon the frame rate allows it: the
    // frames in flight pace the loop (service/submit_pacer.h). Waiting for it, the loop keeps
    // them in flight. The clock's epoch: at once. Called under the loop's lock, like
    // wants_frame().
    virtual std::chrono::steady_clock::time_point next_submit_time() = 0;
    // After every iteration (commands, and a frame if one was due).
    virtual void after_iteration() = 0;
    // Once, after stop(): queued commands have failed with `why`; end streams and free
    // everything. `failed`: the session did not simply close (a lost device), so its streams
    // end with `why` instead of OK.
    virtual void tear_down(const Error& why, bool failed) = 0;
  };
  using Run = std::function<void(Completion)>;  // on the loop thread; completes exactly once

  // `session_id` names the session in errors and logs; `owner` must outlive the loop thread.
  SessionLoop(std::string session_id, double max_fps, Owner& owner);

  // Starts the thread. It holds `keep_alive` until it ended and ran `on_exit` (after teardown
  // and every stop() callback); nobody joins it, so no RPC thread ever waits for a frame.
  void start(std::shared_ptr<void> keep_alive, std::function<void()> on_exit);
  // Queues a command; after stop() `done` fails at once with UNAVAILABLE. `changes_state`:
  // frames after it report it as their newest applied command.
  void enqueue(bool changes_state, Run run, Completion done);
  // The same for commands that finish when `run` returns.
  void enqueue_sync(bool changes_state, std::function<Status()> run, Completion done);
  // Ends the loop after the command running now: the rest fail with UNAVAILABLE (or with
  // `reason`, when given), the owner tears down, then `on_stopped` runs (on the loop thread).
  void stop(std::function<void()> on_stopped, std::optional<Error> reason = std::nullopt);

  // On the loop thread: the command being applied (0 before the first).
  uint64_t applying_seq() const { return applying_seq_; }
  // On the loop thread: frames produced so far.
  uint64_t frames() const { return frames_; }

 private:
  struct Command {
    Run run;
    Completion done;
    uint64_t seq = 0;
    int64_t arrival_unix_us = 0;
    bool changes_state = false;
  };

  void run(const std::shared_ptr<void>& keep_alive, const std::function<void()>& on_exit);
  // Waits for commands or a due frame; false once stopped.
  bool wait_for_work(std::deque<Command>& batch);
  void apply(std::deque<Command>& batch);
  // Someone waits for a frame, the frame rate allows it and the frames in flight ask for it.
  bool frame_due() const;
  void finish();

  const std::string session_id_;
  const std::chrono::steady_clock::duration interval_;
  Owner& owner_;

  // Shared with RPC threads.
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Command> queue_;
  uint64_t next_seq_ = 1;
  bool stopping_ = false;
  std::optional<Error> stop_reason_;  // the first stop() that gave one
  std::vector<std::function<void()>> on_stopped_;

  // Owned by the loop thread.
  uint64_t applying_seq_ = 0;
  CommandStamp last_applied_;
  uint64_t frames_ = 0;
  std::chrono::steady_clock::time_point last_frame_start_{};
};

}  // namespace ddgi::service
