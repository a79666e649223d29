#include "service/chunk_stream.h"

#include <algorithm>

#include "service/grpc_status.h"

namespace ddgi::service {
namespace {
constexpr int kNothing = 0, kWrite = 1, kFinish = 2;
}

template <typename Chunk>
bool ChunkStreamState<Chunk>::prepare_next_locked() {
  chunk_.Clear();
  if (!sent_metadata_) {
    *chunk_.mutable_metadata() = metadata_;
    sent_metadata_ = true;
    return true;
  }
  if (offset_ >= bytes_.size()) return false;
  const size_t size = std::min(chunk_bytes_, bytes_.size() - offset_);
  chunk_.set_offset(offset_);
  chunk_.set_data(bytes_.data() + offset_, size);
  offset_ += size;
  return true;
}

template <typename Chunk>
void ChunkStreamState<Chunk>::deliver(Download dump) {
  int action = kNothing;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_ || reactor_ == nullptr) return;
    if (!dump.ok()) {
      finished_ = true;
      status_ = to_grpc(dump.error());
      action = kFinish;
    } else {
      metadata_ = std::move(dump->first);
      bytes_ = std::move(dump->second);
      have_dump_ = true;
      prepare_next_locked();
      in_flight_ = true;
      action = kWrite;
    }
  }
  act(action);
}

template <typename Chunk>
void ChunkStreamState<Chunk>::finish(const grpc::Status& status) {
  int action = kNothing;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_ || reactor_ == nullptr) return;
    status_ = status;
    if (!in_flight_) {
      finished_ = true;
      action = kFinish;
    } else {
      bytes_.clear();  // stop after the write in flight
      offset_ = 0;
    }
  }
  act(action);
}

template <typename Chunk>
void ChunkStreamState<Chunk>::write_done(bool ok) {
  int action = kNothing;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    in_flight_ = false;
    if (finished_) return;
    if (!ok) {
      status_ = grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
      finished_ = true;
      action = kFinish;
    } else if (status_.ok() && prepare_next_locked()) {
      in_flight_ = true;
      action = kWrite;
    } else {
      finished_ = true;
      action = kFinish;
    }
  }
  act(action);
}

template <typename Chunk>
void ChunkStreamState<Chunk>::cancelled() {
  finish(grpc::Status(grpc::StatusCode::CANCELLED, "the download was cancelled"));
}

template <typename Chunk>
void ChunkStreamState<Chunk>::reactor_done() {
  std::lock_guard<std::mutex> lock(mutex_);
  reactor_ = nullptr;
  finished_ = true;
  bytes_.clear();
  bytes_.shrink_to_fit();
}

template <typename Chunk>
void ChunkStreamState<Chunk>::act(int action) {
  // Without the lock: with a write in flight or Finish pending, OnDone cannot run yet.
  if (action == kWrite) reactor_->StartWrite(&chunk_);
  if (action == kFinish) reactor_->Finish(status_);
}

template <typename Chunk>
ChunkStreamReactor<Chunk>::ChunkStreamReactor(size_t chunk_bytes)
    : state_(std::make_shared<ChunkStreamState<Chunk>>(chunk_bytes)) {
  state_->reactor_ = this;
}

template <typename Chunk>
void ChunkStreamReactor<Chunk>::OnDone() {
  state_->reactor_done();
  delete this;
}

template class ChunkStreamState<v1::AtlasChunk>;
template class ChunkStreamReactor<v1::AtlasChunk>;
template class ChunkStreamState<v1::SceneChunk>;
template class ChunkStreamReactor<v1::SceneChunk>;

}  // namespace ddgi::service
