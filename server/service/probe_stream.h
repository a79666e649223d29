// One StreamProbes call (docs/probe-stream.md): a gRPC ServerWriteReactor that sends a
// session's probes as they change. The session offers a snapshot of the whole field after each
// update; the stream keeps only the newest one, and when it may write it encodes that snapshot
// against what this client already has (the values it last sent, as the client decoded them):
// the probes that moved beyond the threshold, or every probe on a full refresh. So a slow
// reader misses nothing (skipped updates are folded into the next message), costs at most one
// snapshot and its client copy of memory, and never stalls the session. Nothing here blocks.
#pragma once

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "gi/irradiance_field.h"

namespace ddgi::service {

// The whole field after one update, as the stream encodes it (rpc/probe_stream.h's layout).
struct ProbeSnapshot {
  uint64_t field_updates = 0;
  v1::ProbeGrid grid;
  uint32_t stride = 0;  // floats per probe in `values`
  // Values [0, split) and [split, stride) are judged apart for the change threshold (octahedral
  // probes: irradiance, then distances, whose magnitudes differ); SH probes: split = stride.
  uint32_t split = 0;
  std::vector<float> values;  // probe after probe
  std::vector<float> states;  // 4 per probe: offset x, y, z, state
};

// Reads the field back from the GPU (waits for its work).
Result<std::shared_ptr<const ProbeSnapshot>> take_probe_snapshot(IrradianceField& field);

struct ProbeStreamOptions {
  float change_threshold = 0.01f;
  uint32_t full_refresh_interval = 60;
};

class ProbeStreamReactor;

class ProbeStreamState {
 public:
  explicit ProbeStreamState(ProbeStreamOptions options) : options_(options) {}
  // The field after its newest update (any thread).
  void offer(std::shared_ptr<const ProbeSnapshot> snapshot);
  // Ends the stream once the write in flight is done; only the first call counts.
  void finish(const grpc::Status& status);
  bool ended() const;

 private:
  friend class ProbeStreamReactor;
  enum class Action { kNone, kWrite, kFinish };
  // Encodes the slot into writing_ when a write may start, or decides to finish.
  Action next_action_locked();
  void act(Action action);  // without the lock
  void write_done(bool ok);
  void reactor_done();
  // Whether values [begin, end) moved beyond the threshold of their largest magnitude.
  bool moved(const float* now, const float* known, uint32_t begin, uint32_t end) const;
  // Encodes `now` against known_values_/known_states_ and updates them.
  void encode_locked(const ProbeSnapshot& now, bool full);

  const ProbeStreamOptions options_;
  mutable std::mutex mutex_;
  ProbeStreamReactor* reactor_ = nullptr;  // null once gRPC is done with the call
  bool in_flight_ = false;
  bool finish_requested_ = false;
  bool finished_ = false;
  grpc::Status finish_status_;
  std::shared_ptr<const ProbeSnapshot> slot_;
  uint64_t folded_ = 0;        // snapshots replaced in the slot before they were sent
  uint64_t last_updates_ = 0;  // field_updates of the newest snapshot offered
  v1::ProbeUpdate writing_;
  uint64_t messages_ = 0;
  std::string known_grid_;              // the grid the client has, serialized
  std::vector<float> known_values_;     // what the client has, as it decoded it
  std::vector<uint16_t> known_states_;  // fp16, as sent
};

class ProbeStreamReactor : public grpc::ServerWriteReactor<v1::ProbeUpdate> {
 public:
  explicit ProbeStreamReactor(ProbeStreamOptions options);
  const std::shared_ptr<ProbeStreamState>& state() const { return state_; }
  void set_on_done(std::function<void()> on_done) { on_done_ = std::move(on_done); }

  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  std::shared_ptr<ProbeStreamState> state_;
  std::function<void()> on_done_;
};

}  // namespace ddgi::service
