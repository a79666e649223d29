// The task pool (core/task_pool.h).
#include "core/task_pool.h"

#include <algorithm>

namespace ddgi {

TaskPool::TaskPool(unsigned threads) {
  for (unsigned i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
}

TaskPool::~TaskPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

bool TaskPool::claim(Loop& loop, size_t* index) {
  if (loop.next == loop.count) return false;
  *index = loop.next++;
  if (loop.next == loop.count) {
    std::erase_if(queue_,
                  [&](const std::shared_ptr<Loop>& queued) { return queued.get() == &loop; });
  }
  return true;
}

void TaskPool::run_claimed(Loop& loop, size_t index) {
  (*loop.body)(index);
  std::lock_guard<std::mutex> lock(mutex_);
  if (++loop.done == loop.count) finished_.notify_all();
}

void TaskPool::parallel_for(size_t count, const std::function<void(size_t)>& body) {
  if (count == 0) return;
  auto loop = std::make_shared<Loop>();
  loop->body = &body;
  loop->count = count;
  std::unique_lock<std::mutex> lock(mutex_);
  if (count > 1 && !threads_.empty()) {
    queue_.push_back(loop);
    wake_.notify_all();
  }
  size_t index = 0;
  while (claim(*loop, &index)) {
    lock.unlock();
    run_claimed(*loop, index);
    lock.lock();
  }
  finished_.wait(lock, [&] { return loop->done == loop->count; });
}

void TaskPool::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, nothing left to claim
    std::shared_ptr<Loop> loop = queue_.front();
    size_t index = 0;
    if (!claim(*loop, &index)) continue;
    lock.unlock();
    run_claimed(*loop, index);
    lock.lock();
  }
}

}  // namespace ddgi
