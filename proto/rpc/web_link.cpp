#include "rpc/web_link.h"

#include <civetweb.h>
#include <google/protobuf/util/json_util.h>

#include "rpc/web_frame.h"

namespace ddgi {
namespace {

auto deadline_after(double seconds) {
  return std::chrono::steady_clock::now() +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
             std::chrono::duration<double>(seconds));
}

v1::WebReply error_reply(uint64_t id, const char* code, const std::string& message) {
  v1::WebReply reply;
  reply.set_id(id);
  reply.mutable_error()->set_code(code);
  reply.mutable_error()->set_message(message);
  return reply;
}

}  // namespace

Result<std::unique_ptr<WebLink>> WebLink::connect(const std::string& host, int port) {
  std::unique_ptr<WebLink> link(new WebLink());
  char error[256] = {};
  link->connection_ =
      mg_connect_websocket_client(host.c_str(), port, 0, error, sizeof(error), "/ws", nullptr,
                                  &WebLink::on_data, &WebLink::on_close, link.get());
  if (link->connection_ == nullptr) {
    return unavailable("cannot open ws://" + host + ":" + std::to_string(port) +
                       "/ws: " + (error[0] != '\0' ? error : "no reason given"));
  }
  return link;
}

WebLink::~WebLink() {
  if (connection_ != nullptr) mg_close_connection(connection_);
}

void WebLink::send_text(const std::string& text) {
  mg_websocket_client_write(connection_, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
}

void WebLink::send_binary(const std::string& bytes) {
  mg_websocket_client_write(connection_, MG_WEBSOCKET_OPCODE_BINARY, bytes.data(), bytes.size());
}

v1::WebReply WebLink::call(v1::WebRequest request, double seconds) {
  {
    std::lock_guard lock(mutex_);
    request.set_id(next_id_++);
  }
  std::string json;
  (void)google::protobuf::util::MessageToJsonString(request, &json);
  send_text(json);
  v1::WebReply reply;
  if (wait_reply(request.id(), &reply, seconds)) return reply;
  return closed() ? error_reply(request.id(), "UNAVAILABLE", "the web link closed")
                  : error_reply(request.id(), "DEADLINE_EXCEEDED", "no reply in time");
}

bool WebLink::wait_reply(uint64_t id, v1::WebReply* reply, double seconds) {
  std::unique_lock lock(mutex_);
  changed_.wait_until(lock, deadline_after(seconds),
                      [&] { return replies_.count(id) > 0 || closed_; });
  auto first = replies_.find(id);
  if (first == replies_.end()) return false;
  *reply = std::move(first->second);
  replies_.erase(first);
  return true;
}

bool WebLink::next_frame(v1::Frame* frame, double seconds) {
  std::unique_lock lock(mutex_);
  changed_.wait_until(lock, deadline_after(seconds), [&] { return !queue_.empty() || closed_; });
  if (queue_.empty()) return false;
  *frame = std::move(queue_.front());
  queue_.pop_front();
  return true;
}

uint64_t WebLink::frames() const {
  std::lock_guard lock(mutex_);
  return frames_;
}

v1::Frame WebLink::last_frame() const {
  std::lock_guard lock(mutex_);
  return last_frame_;
}

bool WebLink::wait_frames(uint64_t count, double seconds) const {
  std::unique_lock lock(mutex_);
  return changed_.wait_until(lock, deadline_after(seconds), [&] { return frames_ >= count; });
}

bool WebLink::wait_command(uint64_t seq, double seconds) const {
  std::unique_lock lock(mutex_);
  return changed_.wait_until(lock, deadline_after(seconds),
                             [&] { return frames_ > 0 && last_frame_.last_command_seq() >= seq; });
}

bool WebLink::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

int WebLink::on_data(mg_connection*, int bits, char* data, size_t size, void* self) {
  static_cast<WebLink*>(self)->receive(bits & 0xf, data, size);
  return 1;
}

void WebLink::on_close(const mg_connection*, void* self) {
  auto* link = static_cast<WebLink*>(self);
  std::lock_guard lock(link->mutex_);
  link->closed_ = true;
  link->changed_.notify_all();
}

void WebLink::receive(int opcode, const char* data, size_t size) {
  if (opcode == MG_WEBSOCKET_OPCODE_TEXT) {
    v1::WebReply reply;
    if (!google::protobuf::util::JsonStringToMessage(std::string(data, size), &reply).ok()) {
      reply = error_reply(0, "UNPARSEABLE_REPLY", std::string(data, size));
    }
    std::lock_guard lock(mutex_);
    replies_.emplace(reply.id(), std::move(reply));
    changed_.notify_all();
    return;
  }
  if (opcode != MG_WEBSOCKET_OPCODE_BINARY) return;
  Result<v1::Frame> frame = decode_web_frame(std::string_view(data, size));
  if (!frame.ok()) return;  // frames() does not count it: a test waiting for frames sees that
  std::lock_guard lock(mutex_);
  ++frames_;
  last_frame_ = *frame;
  queue_.push_back(std::move(*frame));
  if (queue_.size() > kQueuedFrames) queue_.pop_front();
  changed_.notify_all();
}

}  // namespace ddgi
