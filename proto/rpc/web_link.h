// A C++ client of ddgi-server's web front (web.proto) on civetweb's WebSocket client: what a
// browser does, for scripted clients (ddgi-client stream --web, the WebSocket benchmark) and
// the service tests. Calls are WebRequests sent as JSON and matched to their WebReply by id;
// frames are kept in arrival order (up to kQueuedFrames; older ones are dropped,
// as a browser would skip them) and the newest one is always at hand.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "ddgi/v1/web.pb.h"

struct mg_connection;

namespace ddgi {

class WebLink {
 public:
  static constexpr size_t kQueuedFrames = 16;

  // Connects to ws://host:port/ws (UNAVAILABLE naming why when it cannot).
  static Result<std::unique_ptr<WebLink>> connect(const std::string& host, int port);
  ~WebLink();
  WebLink(const WebLink&) = delete;
  WebLink& operator=(const WebLink&) = delete;

  // Sends one message as it is (tests send malformed ones too).
  void send_text(const std::string& text);
  void send_binary(const std::string& bytes);
  // Sends `request` with a fresh id and waits for its reply; a reply with error code
  // "DEADLINE_EXCEEDED" when none came in time, "UNAVAILABLE" when the connection closed.
  v1::WebReply call(v1::WebRequest request, double seconds = 120.0);
  // Waits for a reply with id `id` (0: refusals of unreadable messages), oldest first.
  bool wait_reply(uint64_t id, v1::WebReply* reply, double seconds = 30.0);

  // The oldest frame not yet taken; false when none came within `seconds` or the link closed.
  bool next_frame(v1::Frame* frame, double seconds = 60.0);
  uint64_t frames() const;       // frames received
  v1::Frame last_frame() const;  // the newest one (jpeg included)
  bool wait_frames(uint64_t count, double seconds = 60.0) const;
  // Waits for a frame whose last_command_seq >= seq.
  bool wait_command(uint64_t seq, double seconds = 60.0) const;
  bool closed() const;

 private:
  WebLink() = default;
  static int on_data(mg_connection* connection, int bits, char* data, size_t size, void* self);
  static void on_close(const mg_connection* connection, void* self);
  void receive(int opcode, const char* data, size_t size);

  mg_connection* connection_ = nullptr;
  uint64_t next_id_ = 1;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::multimap<uint64_t, v1::WebReply> replies_;
  std::deque<v1::Frame> queue_;
  uint64_t frames_ = 0;
  v1::Frame last_frame_;
  bool closed_ = false;
};

}  // namespace ddgi
