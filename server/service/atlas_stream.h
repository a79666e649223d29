// One DumpAtlas call: the metadata, then the atlas bytes in chunks, one write in flight. The
// bytes arrive from the session's loop thread whenever it gets to the request; the state object
// outlives the reactor so a late arrival after the client left is simply dropped.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <mutex>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"

namespace ddgi::service {

class AtlasStreamReactor;

class AtlasStreamState {
 public:
  explicit AtlasStreamState(size_t chunk_bytes) : chunk_bytes_(chunk_bytes) {}
  // The dump is ready (or failed): start sending.
  void deliver(Result<std::pair<v1::AtlasMetadata, std::vector<uint8_t>>> dump);
  void finish(const grpc::Status& status);

 private:
  friend class AtlasStreamReactor;
  bool prepare_next_locked();  // fills chunk_ with the next message; false at the end
  void write_done(bool ok);
  void cancelled();
  void reactor_done();
  void act(int action);  // 0 nothing, 1 write chunk_, 2 finish

  const size_t chunk_bytes_;
  std::mutex mutex_;
  AtlasStreamReactor* reactor_ = nullptr;
  bool in_flight_ = false;
  bool finished_ = false;
  grpc::Status status_;
  bool have_dump_ = false;
  bool sent_metadata_ = false;
  v1::AtlasMetadata metadata_;
  std::vector<uint8_t> bytes_;
  size_t offset_ = 0;
  v1::AtlasChunk chunk_;
};

class AtlasStreamReactor : public grpc::ServerWriteReactor<v1::AtlasChunk> {
 public:
  explicit AtlasStreamReactor(size_t chunk_bytes);
  const std::shared_ptr<AtlasStreamState>& state() const { return state_; }
  void OnWriteDone(bool ok) override { state_->write_done(ok); }
  void OnCancel() override { state_->cancelled(); }
  void OnDone() override;

 private:
  std::shared_ptr<AtlasStreamState> state_;
};

}  // namespace ddgi::service
