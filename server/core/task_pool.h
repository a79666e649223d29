// A fixed set of threads that run the iterations of parallel loops. The frame encoder splits
// one frame's JPEG into strips and compresses them at once, so a frame's encode latency falls
// with the cores instead of only its throughput rising. Several callers may run loops at the
// same time; each caller works on its own loop too, so a loop finishes even when every pool
// thread is busy with another.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace ddgi {

class TaskPool {
 public:
  // `threads`: pool threads besides the callers; 0 runs every loop on its caller.
  explicit TaskPool(unsigned threads);
  ~TaskPool();  // every loop has returned by then (loops block their callers)
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;

  // Runs body(0) .. body(count - 1), on this thread and the pool's, and returns when all have
  // run.
  void parallel_for(size_t count, const std::function<void(size_t)>& body);

 private:
  struct Loop {
    const std::function<void(size_t)>* body = nullptr;
    size_t count = 0;
    size_t next = 0;  // the first iteration nobody has claimed
    size_t done = 0;
  };
  // Claims an iteration of `loop` (under the lock); false when all are claimed.
  bool claim(Loop& loop, size_t* index);
  void run_claimed(Loop& loop, size_t index);  // runs it unlocked, then counts it done
  void work();

  std::mutex mutex_;
  std::condition_variable wake_;             // a loop was queued, or the pool stops
  std::condition_variable finished_;         // some loop's last iteration finished
  std::deque<std::shared_ptr<Loop>> queue_;  // loops with unclaimed iterations
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace ddgi
