// One download call (DumpAtlas, ExportScene): the metadata, then the bytes in chunks, one write
// in flight. The bytes arrive from the session's loop thread (or whoever makes them) whenever it
// gets to the request; the state object outlives the reactor so a late arrival after the client
// left is simply dropped. `Chunk` is a message with `metadata`, `data` and `offset` fields.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <mutex>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"

namespace ddgi::service {

template <typename Chunk>
class ChunkStreamReactor;

template <typename Chunk>
class ChunkStreamState {
 public:
  using Metadata = std::decay_t<decltype(std::declval<Chunk>().metadata())>;
  using Download = Result<std::pair<Metadata, std::vector<uint8_t>>>;

  explicit ChunkStreamState(size_t chunk_bytes) : chunk_bytes_(chunk_bytes) {}
  // The bytes are ready (or failed): start sending.
  void deliver(Download download);
  void finish(const grpc::Status& status);

 private:
  friend class ChunkStreamReactor<Chunk>;
  bool prepare_next_locked();  // fills chunk_ with the next message; false at the end
  void write_done(bool ok);
  void cancelled();
  void reactor_done();
  void act(int action);  // 0 nothing, 1 write chunk_, 2 finish

  const size_t chunk_bytes_;
  std::mutex mutex_;
  ChunkStreamReactor<Chunk>* reactor_ = nullptr;
  bool in_flight_ = false;
  bool finished_ = false;
  grpc::Status status_;
  bool have_dump_ = false;
  bool sent_metadata_ = false;
  Metadata metadata_;
  std::vector<uint8_t> bytes_;
  size_t offset_ = 0;
  Chunk chunk_;
};

template <typename Chunk>
class ChunkStreamReactor : public grpc::ServerWriteReactor<Chunk> {
 public:
  explicit ChunkStreamReactor(size_t chunk_bytes);
  const std::shared_ptr<ChunkStreamState<Chunk>>& state() const { return state_; }
  void OnWriteDone(bool ok) override { state_->write_done(ok); }
  void OnCancel() override { state_->cancelled(); }
  void OnDone() override;

 private:
  std::shared_ptr<ChunkStreamState<Chunk>> state_;
};

using AtlasStreamReactor = ChunkStreamReactor<v1::AtlasChunk>;
using SceneStreamReactor = ChunkStreamReactor<v1::SceneChunk>;

}  // namespace ddgi::service
