// The metrics' parallel loops (metrics/parallel.h) on one process-wide task pool.
#include "metrics/parallel.h"

#include <algorithm>
#include <thread>

#include "core/task_pool.h"

namespace ddgi::metrics {

namespace {

TaskPool& metrics_pool() {
  static TaskPool pool(std::max(1u, std::thread::hardware_concurrency()) - 1);
  return pool;
}

}  // namespace

void for_each_chunk(size_t count, size_t chunk, const std::function<void(size_t, size_t)>& body) {
  const size_t chunks = (count + chunk - 1) / chunk;
  metrics_pool().parallel_for(chunks,
                              [&](size_t i) { body(i * chunk, std::min(count, (i + 1) * chunk)); });
}

}  // namespace ddgi::metrics
