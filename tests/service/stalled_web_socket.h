// A stalled browser for the web front's tests (server/service/web_gateway.h; the well-behaved
// one is rpc/web_link.h): a raw socket with a tiny receive buffer that completes the
// handshake, asks for a stream, and stops reading when told.
#pragma once

#include <atomic>
#include <string>
#include <thread>

namespace ddgi::test {

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
