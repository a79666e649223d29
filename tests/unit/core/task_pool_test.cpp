// The task pool (core/task_pool.h): every iteration runs exactly once, loops from several
// callers at once all finish, the pool's threads share the work, and a pool without threads
// runs loops on their callers.
#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <thread>
#include <vector>

#include "core/task_pool.h"

namespace ddgi {
namespace {

TEST(TaskPool, EveryIterationRunsOnceWithManyCallers) {
  TaskPool pool(3);
  constexpr size_t kCallers = 4, kLoops = 50, kCount = 37;
  std::vector<std::vector<std::atomic<int>>> runs(kCallers);
  for (auto& caller : runs) caller = std::vector<std::atomic<int>>(kCount);
  std::vector<std::thread> callers;
  for (size_t c = 0; c < kCallers; ++c) {
    callers.emplace_back([&, c] {
      for (size_t loop = 0; loop < kLoops; ++loop) {
        pool.parallel_for(kCount, [&](size_t i) { runs[c][i].fetch_add(1); });
      }
    });
  }
  for (std::thread& t : callers) t.join();
  for (size_t c = 0; c < kCallers; ++c) {
    for (size_t i = 0; i < kCount; ++i) EXPECT_EQ(runs[c][i].load(), int(kLoops)) << c << "," << i;
  }
}

// Iterations that wait for each other can only finish when they run at the same time: with 3
// pool threads and the caller, 4 iterations meet at a barrier.
TEST(TaskPool, IterationsRunConcurrently) {
  TaskPool pool(3);
  std::atomic<int> arrived{0};
  std::mutex mutex;
  std::set<std::thread::id> threads;
  pool.parallel_for(4, [&](size_t) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      threads.insert(std::this_thread::get_id());
    }
    arrived.fetch_add(1);
    while (arrived.load() < 4) std::this_thread::yield();
  });
  EXPECT_EQ(threads.size(), 4u);
}

TEST(TaskPool, WithoutThreadsTheCallerRunsEverything) {
  TaskPool pool(0);
  std::vector<int> order;
  pool.parallel_for(5, [&](size_t i) { order.push_back(int(i)); });
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
  pool.parallel_for(0, [&](size_t) { order.push_back(-1); });
  EXPECT_EQ(order.size(), 5u);
}

}  // namespace
}  // namespace ddgi
