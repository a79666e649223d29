#include "service/frame_encoder.h"

#include <algorithm>
#include <chrono>

#include "core/log.h"
#include "encode/jpeg.h"
#include "service/grpc_status.h"

namespace ddgi::service {

FrameEncoder::FrameEncoder(unsigned threads, Metrics& metrics)
    : metrics_(metrics), max_strips_(std::max(1u, threads)), strip_pool_(max_strips_ - 1) {
  for (unsigned i = 0; i < max_strips_; ++i) threads_.emplace_back([this] { work(); });
}

FrameEncoder::~FrameEncoder() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void FrameEncoder::submit(std::unique_ptr<EncodeJob> job) {
  // A queued job this one replaces is counted as dropped by its streams when this one arrives.
  for (auto& stream : job->streams) stream->expect(job->frame.frame_index());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& queued : queue_) {
      if (queued->view_key != job->view_key) continue;
      job->waiters.insert(job->waiters.begin(), std::make_move_iterator(queued->waiters.begin()),
                          std::make_move_iterator(queued->waiters.end()));
      queued = std::move(job);
      return;
    }
    queue_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void FrameEncoder::work() {
  while (true) {
    std::unique_ptr<EncodeJob> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    run(*job);
  }
}

void FrameEncoder::run(EncodeJob& job) {
  const auto start = std::chrono::steady_clock::now();
  Result<std::vector<uint8_t>> jpeg =
      encode::encode_jpeg_strips(job.image, job.quality, max_strips_,
                                 [this](size_t count, const std::function<void(size_t)>& body) {
                                   strip_pool_.parallel_for(count, body);
                                 });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The Frame's other fields (camera, pass times, ids) take well under this.
  constexpr uint64_t kFrameFieldsBytes = 4096;
  if (jpeg.ok() && job.max_frame_bytes && jpeg->size() + kFrameFieldsBytes > job.max_frame_bytes) {
    const uint64_t room = job.max_frame_bytes - std::min(job.max_frame_bytes, kFrameFieldsBytes);
    jpeg = resource_exhausted(
        "a " + std::to_string(job.frame.width()) + "x" + std::to_string(job.frame.height()) +
        " frame encoded to " + std::to_string(jpeg->size()) + " bytes; the message limit of " +
        std::to_string(job.max_frame_bytes) + " bytes (--max-message-bytes) leaves room for " +
        std::to_string(room) + "; lower the size or JPEG quality");
  }
  if (!jpeg.ok()) {
    LOG_WARNING << "frame encoding failed view=" << job.view_key << ": " << jpeg.error().message;
    for (auto& stream : job.streams) stream->finish(to_grpc(jpeg.error()));
    for (auto& waiter : job.waiters) waiter(jpeg.error());
    return;
  }
  metrics_.encode_seconds.observe(seconds);
  auto frame = std::make_shared<v1::Frame>(std::move(job.frame));
  frame->set_jpeg(jpeg->data(), jpeg->size());
  frame->set_encode_ms(seconds * 1e3);
  std::shared_ptr<const v1::Frame> shared = std::move(frame);
  for (auto& stream : job.streams) stream->offer(shared);
  for (auto& waiter : job.waiters) waiter(shared);
}

}  // namespace ddgi::service
