// A browser stand-in for the web front's tests (server/service/web_gateway.h): a WebSocket
// client on civetweb's client API that sends WebRequests as JSON, waits for the WebReply of a
// given id, and keeps the frames it receives (count, newest header, newest JPEG). Also a
// stalled browser: a raw socket with a tiny receive buffer that completes the handshake, asks
// for a stream and then never reads again.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "ddgi/v1/render_service.pb.h"
#include "ddgi/v1/web.pb.h"

struct mg_connection;

namespace ddgi::test {

class WebSocketClient {
 public:
  // Connects to ws://127.0.0.1:port/ws; connected() says whether the handshake succeeded.
  explicit WebSocketClient(int port);
  ~WebSocketClient();
  bool connected() const { return connection_ != nullptr; }
  const std::string& connect_error() const { return error_; }

  // Sends `json` as one text message (anything: the tests send malformed ones too).
  void send_text(const std::string& json);
  void send_binary(const std::string& bytes);
  // Sends `request` (its id set to a fresh one) and waits for the reply with that id.
  v1::WebReply call(v1::WebRequest request, double seconds = 120.0);
  // Waits for a reply with id `id` (0: the refusals of unreadable messages), in arrival order.
  bool wait_reply(uint64_t id, v1::WebReply* reply, double seconds = 30.0);

  uint64_t frames() const;
  v1::Frame last_frame() const;  // header fields and jpeg
  // Waits until frames() >= count.
  bool wait_frames(uint64_t count, double seconds = 60.0) const;
  // Waits for a frame whose last_command_seq >= seq.
  bool wait_command(uint64_t seq, double seconds = 60.0) const;
  bool closed() const;

 private:
  static int on_data(mg_connection* connection, int bits, char* data, size_t size, void* self);
  static void on_close(const mg_connection* connection, void* self);
  void receive(int opcode, const char* data, size_t size);

  mg_connection* connection_ = nullptr;
  std::string error_;
  uint64_t next_id_ = 1;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::multimap<uint64_t, v1::WebReply> replies_;
  uint64_t frames_ = 0;
  v1::Frame last_frame_;
  bool closed_ = false;
};

// A browser that stops reading: connects with a 4 KiB receive buffer, sends `request_json` as
// one text message after the handshake, reads (and discards) what comes until stall(), and
// nothing after it.
class StalledWebSocket {
 public:
  StalledWebSocket(int port, const std::string& request_json);
  ~StalledWebSocket();
  bool ok() const { return fd_ >= 0; }
  // Stops reading (returns once the reading thread has stopped).
  void stall();

 private:
  int fd_ = -1;
  std::atomic<bool> reading_{true};
  std::thread reader_;
};

}  // namespace ddgi::test
