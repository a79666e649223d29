#include "tests/service/web_socket_client.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <google/protobuf/util/json_util.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

namespace ddgi::test {
namespace {

auto deadline_after(double seconds) {
  return std::chrono::steady_clock::now() +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
             std::chrono::duration<double>(seconds));
}

}  // namespace

WebSocketClient::WebSocketClient(int port) {
  char error[256] = {};
  connection_ =
      mg_connect_websocket_client("127.0.0.1", port, 0, error, sizeof(error), "/ws", nullptr,
                                  &WebSocketClient::on_data, &WebSocketClient::on_close, this);
  if (connection_ == nullptr) error_ = error;
}

WebSocketClient::~WebSocketClient() {
  if (connection_ != nullptr) mg_close_connection(connection_);
}

void WebSocketClient::send_text(const std::string& json) {
  mg_websocket_client_write(connection_, MG_WEBSOCKET_OPCODE_TEXT, json.data(), json.size());
}

void WebSocketClient::send_binary(const std::string& bytes) {
  mg_websocket_client_write(connection_, MG_WEBSOCKET_OPCODE_BINARY, bytes.data(), bytes.size());
}

v1::WebReply WebSocketClient::call(v1::WebRequest request, double seconds) {
  request.set_id(next_id_++);
  std::string json;
  (void)google::protobuf::util::MessageToJsonString(request, &json);
  send_text(json);
  v1::WebReply reply;
  if (!wait_reply(request.id(), &reply, seconds)) {
    reply.mutable_error()->set_code("TEST_TIMEOUT");
    reply.mutable_error()->set_message("no reply within the test's deadline");
  }
  return reply;
}

bool WebSocketClient::wait_reply(uint64_t id, v1::WebReply* reply, double seconds) {
  std::unique_lock lock(mutex_);
  if (!changed_.wait_until(lock, deadline_after(seconds),
                           [&] { return replies_.count(id) > 0 || closed_; }) ||
      replies_.count(id) == 0) {
    return false;
  }
  auto first = replies_.find(id);
  *reply = first->second;
  replies_.erase(first);
  return true;
}

uint64_t WebSocketClient::frames() const {
  std::lock_guard lock(mutex_);
  return frames_;
}

v1::Frame WebSocketClient::last_frame() const {
  std::lock_guard lock(mutex_);
  return last_frame_;
}

bool WebSocketClient::wait_frames(uint64_t count, double seconds) const {
  std::unique_lock lock(mutex_);
  return changed_.wait_until(lock, deadline_after(seconds), [&] { return frames_ >= count; });
}

bool WebSocketClient::wait_command(uint64_t seq, double seconds) const {
  std::unique_lock lock(mutex_);
  return changed_.wait_until(lock, deadline_after(seconds),
                             [&] { return frames_ > 0 && last_frame_.last_command_seq() >= seq; });
}

bool WebSocketClient::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

int WebSocketClient::on_data(mg_connection*, int bits, char* data, size_t size, void* self) {
  static_cast<WebSocketClient*>(self)->receive(bits & 0xf, data, size);
  return 1;
}

void WebSocketClient::on_close(const mg_connection*, void* self) {
  auto* client = static_cast<WebSocketClient*>(self);
  std::lock_guard lock(client->mutex_);
  client->closed_ = true;
  client->changed_.notify_all();
}

void WebSocketClient::receive(int opcode, const char* data, size_t size) {
  if (opcode == MG_WEBSOCKET_OPCODE_TEXT) {
    v1::WebReply reply;
    if (!google::protobuf::util::JsonStringToMessage(std::string(data, size), &reply).ok()) {
      reply.mutable_error()->set_code("TEST_UNPARSEABLE_REPLY");
      reply.mutable_error()->set_message(std::string(data, size));
    }
    std::lock_guard lock(mutex_);
    replies_.emplace(reply.id(), reply);
    changed_.notify_all();
  } else if (opcode == MG_WEBSOCKET_OPCODE_BINARY && size >= 4) {
    uint32_t length = 0;
    for (int byte = 0; byte < 4; ++byte) length |= uint32_t(uint8_t(data[byte])) << (8 * byte);
    v1::Frame frame;
    if (4 + size_t(length) > size ||
        !google::protobuf::util::JsonStringToMessage(std::string(data + 4, length), &frame).ok()) {
      return;  // frames() does not count it: the tests see the loss
    }
    frame.set_jpeg(std::string(data + 4 + length, size - 4 - length));
    std::lock_guard lock(mutex_);
    ++frames_;
    last_frame_ = std::move(frame);
    changed_.notify_all();
  }
}

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
