#include "service/metrics.h"

#include <cstdio>

namespace ddgi::service {
namespace {

std::string number(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

void write_scalar(std::string& out, const std::string& name, const char* type,
                  const std::string& help, double value) {
  out += "# HELP " + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  out += name + " " + number(value) + "\n";
}

// Frame and pass times run from sub-millisecond (an H100) to seconds (lavapipe at 1080p).
std::vector<double> time_buckets() {
  return {0.0005, 0.001, 0.002, 0.004, 0.008, 0.016, 0.033, 0.066, 0.125, 0.25, 0.5, 1, 2, 4, 8};
}

}  // namespace

Histogram::Histogram(std::vector<double> bounds)
    : bounds_(std::move(bounds)), counts_(bounds_.size() + 1, 0) {}

void Histogram::observe(double value) {
  size_t bucket = 0;
  while (bucket < bounds_.size() && value > bounds_[bucket]) ++bucket;
  std::lock_guard<std::mutex> lock(mutex_);
  ++counts_[bucket];
  sum_ += value;
  ++count_;
}

void Histogram::write(std::string& out, const std::string& name, const std::string& help) const {
  std::lock_guard<std::mutex> lock(mutex_);
  out += "# HELP " + name + " " + help + "\n# TYPE " + name + " histogram\n";
  uint64_t cumulative = 0;
  for (size_t i = 0; i < bounds_.size(); ++i) {
    cumulative += counts_[i];
    out += name + "_bucket{le=\"" + number(bounds_[i]) + "\"} " + std::to_string(cumulative) + "\n";
  }
  cumulative += counts_.back();
  out += name + "_bucket{le=\"+Inf\"} " + std::to_string(cumulative) + "\n";
  out += name + "_sum " + number(sum_) + "\n";
  out += name + "_count " + std::to_string(count_) + "\n";
}

Metrics::Metrics()
    : frame_seconds(time_buckets()),
      gi_update_seconds(time_buckets()),
      encode_seconds(time_buckets()) {}

void Metrics::count_rpc(const std::string& method, const std::string& code) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++rpcs_[{method, code}];
}

void Metrics::add_gauge(std::string name, std::string help, std::function<double()> read) {
  std::lock_guard<std::mutex> lock(mutex_);
  gauges_.push_back({std::move(name), std::move(help), std::move(read)});
}

std::string Metrics::prometheus_text() const {
  std::string out;
  write_scalar(out, "ddgi_sessions", "gauge", "Open sessions.", double(sessions.load()));
  write_scalar(out, "ddgi_views", "gauge", "Views over all sessions.", double(views.load()));
  write_scalar(out, "ddgi_streams", "gauge", "Open StreamFrames calls.", double(streams.load()));
  write_scalar(out, "ddgi_sessions_created_total", "counter", "Sessions created.",
               double(sessions_created.load()));
  write_scalar(out, "ddgi_frames_rendered_total", "counter", "View frames rendered.",
               double(frames_rendered.load()));
  write_scalar(out, "ddgi_frames_pipelined_total", "counter",
               "View frames submitted while an earlier frame of their session was not yet read "
               "back.",
               double(frames_pipelined.load()));
  write_scalar(out, "ddgi_frames_sent_total", "counter", "Frames written to streams.",
               double(frames_sent.load()));
  write_scalar(out, "ddgi_frames_dropped_total", "counter",
               "Frames a stream skipped because a newer one replaced it before it was sent.",
               double(frames_dropped.load()));
  write_scalar(out, "ddgi_field_updates_total", "counter", "Irradiance field updates.",
               double(field_updates.load()));
  write_scalar(out, "ddgi_world_cache_entries", "gauge",
               "Live entries of the sessions' world caches.", double(world_cache_entries.load()));
  write_scalar(out, "ddgi_world_cache_inserted_total", "counter",
               "Points that got a world-cache entry.", double(world_cache_inserted.load()));
  write_scalar(out, "ddgi_world_cache_evicted_total", "counter",
               "World-cache entries freed after max_age frames unsampled.",
               double(world_cache_evicted.load()));
  write_scalar(out, "ddgi_world_cache_dropped_total", "counter",
               "Samples a world cache could not keep: no free slot near their key.",
               double(world_cache_dropped.load()));
  write_scalar(out, "ddgi_world_cache_checksum_rejects_total", "counter",
               "World-cache probes that met their key held by another point (kept apart).",
               double(world_cache_checksum_rejects.load()));
  write_scalar(out, "ddgi_web_connections", "gauge", "Open WebSockets of the web front.",
               double(web_connections.load()));
  write_scalar(out, "ddgi_web_frames_sent_total", "counter", "Frames written to WebSockets.",
               double(web_frames_sent.load()));
  write_scalar(out, "ddgi_web_frames_dropped_total", "counter",
               "Frames a WebSocket skipped because a newer one came before it was sent.",
               double(web_frames_dropped.load()));
  write_scalar(out, "ddgi_web_messages_refused_total", "counter",
               "WebSocket messages refused before any call (not JSON, not a WebRequest, "
               "binary, too large).",
               double(web_messages_refused.load()));
  frame_seconds.write(out, "ddgi_frame_seconds",
                      "Wall time to render one view's frame (GPU submission and readback).");
  gi_update_seconds.write(out, "ddgi_gi_update_seconds",
                          "GPU time of one irradiance field update.");
  encode_seconds.write(out, "ddgi_encode_seconds", "Time to JPEG-encode one frame.");
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Gauge& gauge : gauges_) {
    write_scalar(out, gauge.name, "gauge", gauge.help, gauge.read());
  }
  if (!rpcs_.empty()) {
    out += "# HELP ddgi_rpcs_total Finished RPCs by method and status code.\n";
    out += "# TYPE ddgi_rpcs_total counter\n";
    for (const auto& [key, count] : rpcs_) {
      out += "ddgi_rpcs_total{method=\"" + key.first + "\",code=\"" + key.second + "\"} " +
             std::to_string(count) + "\n";
    }
  }
  return out;
}

}  // namespace ddgi::service
