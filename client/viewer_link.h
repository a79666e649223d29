// The viewer's network side, off the UI thread: one thread reads the frame stream and decodes
// each JPEG into a latest-frame slot (older undisplayed frames are simply replaced), another
// sends camera moves, one RPC in flight and only the newest pending camera, so dragging the
// mouse over a slow link queues nothing. Latency = time from sending a camera to the first
// frame whose last_command_seq shows it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "connection.h"
#include "ddgi/v1/render_service.grpc.pb.h"
#include "encode/image.h"

namespace ddgi::client {

struct ViewerFrame {
  encode::ImageRgba8 image;
  v1::Frame info;  // without the JPEG bytes
};

struct LinkStats {
  double latency_ms = 0.0;  // of the newest measured camera move; 0 until one is measured
  uint64_t frames = 0;
};

class ViewerLink {
 public:
  ViewerLink(const ConnectionOptions& connection, v1::StreamFramesRequest request);
  ~ViewerLink();

  // The newest decoded frame not yet taken.
  std::optional<ViewerFrame> take_frame();
  // Asks for `camera` on the stream's view (coalesced with earlier unsent ones).
  void move_camera(const v1::Camera& camera);
  LinkStats stats() const;
  // Set when the stream ended; `status` says how.
  bool ended() const { return ended_.load(); }
  grpc::Status status() const;

 private:
  void read_frames();
  void send_cameras();

  ConnectionOptions connection_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::RenderService::Stub> stub_;
  grpc::ClientContext stream_context_;
  std::unique_ptr<grpc::ClientReader<v1::Frame>> reader_;

  mutable std::mutex mutex_;
  std::condition_variable camera_wanted_;
  std::optional<ViewerFrame> latest_;
  std::string session_id_, view_id_;
  std::optional<v1::Camera> pending_camera_;
  struct Probe {
    uint64_t seq;
    std::chrono::steady_clock::time_point sent;
  };
  std::deque<Probe> probes_;
  LinkStats stats_;
  grpc::Status status_;
  std::atomic<bool> ended_{false};
  std::atomic<bool> stopping_{false};
  std::thread reader_thread_;
  std::thread camera_thread_;
};

}  // namespace ddgi::client
