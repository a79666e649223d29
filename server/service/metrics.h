// Server metrics in the Prometheus text format (version 0.0.4), served by metrics_http.h.
// Names and meanings are listed in docs/service.md.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace ddgi::service {

// A Prometheus histogram with fixed bucket bounds (seconds), safe to observe from any thread.
class Histogram {
 public:
  explicit Histogram(std::vector<double> bounds);
  void observe(double value);
  void write(std::string& out, const std::string& name, const std::string& help) const;

 private:
  std::vector<double> bounds_;
  mutable std::mutex mutex_;
  std::vector<uint64_t> counts_;  // per bucket, not cumulative; last: +Inf
  double sum_ = 0.0;
  uint64_t count_ = 0;
};

class Metrics {
 public:
  Metrics();

  std::atomic<int64_t> sessions{0};
  std::atomic<int64_t> views{0};
  std::atomic<int64_t> streams{0};
  std::atomic<uint64_t> sessions_created{0};
  std::atomic<uint64_t> frames_rendered{0};
  // View frames submitted while an earlier frame of their session was not yet read back.
  std::atomic<uint64_t> frames_pipelined{0};
  std::atomic<uint64_t> frames_sent{0};
  std::atomic<uint64_t> frames_dropped{0};
  std::atomic<uint64_t> field_updates{0};
  // The world caches of sessions in the ao-cache mode (docs/world-cache.md): live entries over
  // all sessions, and what their frames did (reported after each finished frame).
  std::atomic<int64_t> world_cache_entries{0};
  std::atomic<uint64_t> world_cache_inserted{0};
  std::atomic<uint64_t> world_cache_evicted{0};
  std::atomic<uint64_t> world_cache_dropped{0};
  std::atomic<uint64_t> world_cache_checksum_rejects{0};
  // The web front (web_gateway.h): open WebSockets, frames written to them and skipped for
  // browsers that read slower than frames come, text messages refused before any RPC.
  std::atomic<int64_t> web_connections{0};
  std::atomic<uint64_t> web_frames_sent{0};
  std::atomic<uint64_t> web_frames_dropped{0};
  std::atomic<uint64_t> web_messages_refused{0};

  Histogram frame_seconds;      // wall time of one view's frame, from recording to readback
  Histogram gi_update_seconds;  // GPU time of one field update
  Histogram encode_seconds;     // JPEG encoding of one frame

  // Counts one finished RPC by method and status code name.
  void count_rpc(const std::string& method, const std::string& code);
  // Values read when scraped (e.g. GPU memory in use).
  void add_gauge(std::string name, std::string help, std::function<double()> read);

  std::string prometheus_text() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, uint64_t> rpcs_;
  struct Gauge {
    std::string name, help;
    std::function<double()> read;
  };
  std::vector<Gauge> gauges_;
};

}  // namespace ddgi::service
