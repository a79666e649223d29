#include "viewer_link.h"

#include "encode/jpeg.h"

namespace ddgi::client {

ViewerLink::ViewerLink(const ConnectionOptions& connection, v1::StreamFramesRequest request)
    : connection_(connection), channel_(make_channel(connection)) {
  stub_ = v1::RenderService::NewStub(channel_);
  prepare(stream_context_, connection_, false);
  session_id_ = request.session_id();
  reader_ = stub_->StreamFrames(&stream_context_, request);
  reader_thread_ = std::thread([this] { read_frames(); });
  camera_thread_ = std::thread([this] { send_cameras(); });
}

ViewerLink::~ViewerLink() {
  stopping_ = true;
  stream_context_.TryCancel();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    camera_wanted_.notify_all();
  }
  reader_thread_.join();
  camera_thread_.join();
}

void ViewerLink::read_frames() {
  v1::Frame frame;
  while (reader_->Read(&frame)) {
    const auto now = std::chrono::steady_clock::now();
    const auto* data = reinterpret_cast<const uint8_t*>(frame.jpeg().data());
    auto image = encode::decode_jpeg({data, frame.jpeg().size()});
    if (!image.ok()) continue;  // a broken frame is skipped; the next one replaces it
    frame.clear_jpeg();
    std::lock_guard<std::mutex> lock(mutex_);
    view_id_ = frame.view_id();
    while (!probes_.empty() && probes_.front().seq <= frame.last_command_seq()) {
      stats_.latency_ms =
          std::chrono::duration<double, std::milli>(now - probes_.front().sent).count();
      probes_.pop_front();
    }
    ++stats_.frames;
    latest_ = ViewerFrame{std::move(image).value(), frame};
  }
  const grpc::Status status = reader_->Finish();
  std::lock_guard<std::mutex> lock(mutex_);
  status_ = status;
  ended_ = true;
  camera_wanted_.notify_all();
}

void ViewerLink::send_cameras() {
  while (true) {
    v1::SetCameraRequest request;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      camera_wanted_.wait(
          lock, [&] { return stopping_ || ended_ || (pending_camera_ && !view_id_.empty()); });
      if (stopping_ || ended_) return;
      request.set_session_id(session_id_);
      request.set_view_id(view_id_);
      *request.mutable_camera() = *pending_camera_;
      pending_camera_.reset();
    }
    grpc::ClientContext context;
    prepare(context, connection_);
    v1::ViewInfo reply;
    const auto sent = std::chrono::steady_clock::now();
    if (stub_->SetCamera(&context, request, &reply).ok()) {
      std::lock_guard<std::mutex> lock(mutex_);
      probes_.push_back({reply.command_seq(), sent});
      if (probes_.size() > 64) probes_.pop_front();
    }
  }
}

std::optional<ViewerFrame> ViewerLink::take_frame() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::optional<ViewerFrame> frame = std::move(latest_);
  latest_.reset();
  return frame;
}

void ViewerLink::move_camera(const v1::Camera& camera) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_camera_ = camera;
  camera_wanted_.notify_all();
}

LinkStats ViewerLink::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

grpc::Status ViewerLink::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return status_;
}

}  // namespace ddgi::client
