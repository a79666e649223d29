#include "tests/service/stalled_web_socket.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

namespace ddgi::test {
StalledWebSocket::StalledWebSocket(int port, const std::string& request_json) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int receive_buffer = 4096;  // before connect, so the window it advertises stays small
  setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof(receive_buffer));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    ::close(fd);
    return;
  }
  const std::string handshake =
      "GET /ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
  (void)::send(fd, handshake.data(), handshake.size(), MSG_NOSIGNAL);
  // The 101 reply ends with an empty line; read it byte by byte so nothing after it is taken.
  std::string reply;
  char c = 0;
  while (reply.find("\r\n\r\n") == std::string::npos && ::recv(fd, &c, 1, 0) == 1) reply += c;
  if (reply.rfind("HTTP/1.1 101", 0) != 0) {
    ::close(fd);
    return;
  }
  // One masked text frame (clients must mask): FIN + text, length, key, payload ^ key.
  const uint8_t key[4] = {0x12, 0x34, 0x56, 0x78};
  std::string frame = {char(0x81)};
  const size_t size = request_json.size();
  if (size < 126) {
    frame += char(0x80 | size);
  } else {
    frame += char(0x80 | 126);
    frame += char((size >> 8) & 0xff);
    frame += char(size & 0xff);
  }
  frame.append(reinterpret_cast<const char*>(key), 4);
  for (size_t i = 0; i < size; ++i) frame += char(request_json[i] ^ key[i % 4]);
  (void)::send(fd, frame.data(), frame.size(), MSG_NOSIGNAL);
  fd_ = fd;
  reader_ = std::thread([this] {
    char buffer[4096];
    while (reading_) {
      pollfd ready{fd_, POLLIN, 0};
      if (::poll(&ready, 1, 20) > 0 && ::recv(fd_, buffer, sizeof(buffer), 0) <= 0) break;
    }
  });
}

void StalledWebSocket::stall() {
  reading_ = false;
  if (reader_.joinable()) reader_.join();
}

StalledWebSocket::~StalledWebSocket() {
  stall();
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace ddgi::test
