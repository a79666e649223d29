// JPEG encoding on worker threads. The frame loop hands over a rendered view and goes on with
// the next frame; at most one job per view waits in the queue: a newer frame of the same view
// replaces the waiting one (its streams count a drop, its one-shot waiters move to the newer
// frame), so a slow encoder bounds memory instead of building a backlog. A worker compresses
// its frame in strips at once (encode_jpeg_strips) with the strip pool's threads, so a large
// frame's encode latency falls with the cores.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/result.h"
#include "core/task_pool.h"
#include "ddgi/v1/render_service.pb.h"
#include "encode/image.h"
#include "service/frame_stream.h"
#include "service/metrics.h"

namespace ddgi::service {

// A unary RenderFrame waiting for its frame; called exactly once.
using FrameWaiter = std::function<void(Result<std::shared_ptr<const v1::Frame>>)>;

struct EncodeJob {
  std::string view_key;       // jobs with the same key replace each other while queued
  encode::ImageYuv420 image;  // JPEG's colour space already (FrameSettings::read_yuv420)
  int quality = 85;
  v1::Frame frame;  // everything but the JPEG bytes and the encode time
  uint64_t max_frame_bytes = 0;
  std::vector<std::shared_ptr<FrameStreamState>> streams;
  std::vector<FrameWaiter> waiters;
};

class FrameEncoder {
 public:
  // `threads` workers and `threads` - 1 strip threads: a frame is cut into at most `threads`
  // strips, its worker compressing one of them.
  FrameEncoder(unsigned threads, Metrics& metrics);
  ~FrameEncoder();  // encodes what is queued, then joins
  FrameEncoder(const FrameEncoder&) = delete;
  FrameEncoder& operator=(const FrameEncoder&) = delete;

  void submit(std::unique_ptr<EncodeJob> job);

 private:
  void work();
  void run(EncodeJob& job);

  Metrics& metrics_;
  unsigned max_strips_;
  TaskPool strip_pool_;  // declared before the workers, which use it until joined
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::unique_ptr<EncodeJob>> queue_;
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace ddgi::service
