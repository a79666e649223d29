// The Prometheus endpoint (service/metrics_http.h) over real loopback sockets: what it answers
// for each path and method, and that slow clients (slowloris: one byte a second, never
// finishing their request) neither delay a concurrent scrape nor hold a connection past the
// per-request deadline. No GPU: the endpoint is started on its own with a fixed body.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "service/metrics_http.h"

namespace ddgi::test {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

int connect_loopback(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// Reads until the peer closes or `deadline_s` passes; true when the peer closed.
bool read_until_closed(int fd, double deadline_s, std::string* out) {
  const auto start = Clock::now();
  char buffer[4096];
  while (seconds_since(start) < deadline_s) {
    pollfd p{fd, POLLIN, 0};
    const int left_ms = static_cast<int>((deadline_s - seconds_since(start)) * 1000) + 1;
    if (::poll(&p, 1, left_ms) <= 0) continue;
    const ssize_t n = ::recv(fd, buffer, sizeof(buffer), 0);
    if (n <= 0) return true;
    out->append(buffer, static_cast<size_t>(n));
  }
  return false;
}

struct Reply {
  std::string text;  // status line, headers and body; empty when nothing came in time
  double seconds = 0.0;
};

// One request on a fresh connection; the whole exchange bounded by `deadline_s`.
Reply exchange(int port, const std::string& request, double deadline_s = 20.0) {
  Reply reply;
  const auto start = Clock::now();
  const int fd = connect_loopback(port);
  if (fd < 0) return reply;
  ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  read_until_closed(fd, deadline_s, &reply.text);
  ::close(fd);
  reply.seconds = seconds_since(start);
  return reply;
}

std::string header_block(const std::string& reply) {
  return reply.substr(0, reply.find("\r\n\r\n"));
}

std::string body_of(const std::string& reply) {
  const size_t end = reply.find("\r\n\r\n");
  return end == std::string::npos ? "" : reply.substr(end + 4);
}

// A slowloris client: connects and sends one byte of a request that never ends every
// `interval_s`, at most `bytes` of them (a bounded loop), unless the server closes first.
class SlowClient {
 public:
  SlowClient(int port, int bytes, double interval_s) {
    fd_ = connect_loopback(port);
    thread_ = std::thread([this, bytes, interval_s] {
      const std::string request = "GET /metrics HTTP/1.1\r\nX-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaa";
      const auto start = Clock::now();
      for (int i = 0; i < bytes && !stop_; ++i) {
        if (::send(fd_, &request[static_cast<size_t>(i) % request.size()], 1, MSG_NOSIGNAL) != 1) {
          break;
        }
        sent_ = i + 1;
        // Anything from the server (an error reply, or the close) ends the request.
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(interval_s * 1000)) > 0) break;
      }
      held_s_ = seconds_since(start);
      done_ = true;
    });
  }
  ~SlowClient() {
    stop_ = true;
    join();
    if (fd_ >= 0) ::close(fd_);
  }
  bool connected() const { return fd_ >= 0; }
  bool done() const { return done_; }
  int sent() const { return sent_; }
  double held_seconds() const { return held_s_; }
  void join() {
    if (thread_.joinable()) thread_.join();
  }

 private:
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<bool> done_{false};
  std::atomic<int> sent_{0};
  std::atomic<double> held_s_{0.0};
  std::thread thread_;
};

std::unique_ptr<service::MetricsHttpServer> start_endpoint() {
  auto server = service::MetricsHttpServer::start(
      "127.0.0.1", 0, [] { return std::string("# TYPE ddgi_sessions gauge\nddgi_sessions 3\n"); });
  EXPECT_TRUE(server.ok()) << server.error().message;
  return server.ok() ? std::move(server).value() : nullptr;
}

TEST(MetricsHttpTest, ServesMetricsAnd404ElsewhereAnd400ForOtherMethods) {
  auto server = start_endpoint();
  ASSERT_NE(server, nullptr);
  ASSERT_GT(server->port(), 0);

  const Reply ok = exchange(server->port(), "GET /metrics HTTP/1.0\r\n\r\n");
  EXPECT_EQ(ok.text.rfind("HTTP/1.", 0), 0u) << ok.text;
  EXPECT_NE(ok.text.find(" 200 OK\r\n"), std::string::npos) << ok.text;
  EXPECT_NE(header_block(ok.text).find("Content-Type: text/plain; version=0.0.4; charset=utf-8"),
            std::string::npos)
      << ok.text;
  EXPECT_EQ(body_of(ok.text), "# TYPE ddgi_sessions gauge\nddgi_sessions 3\n");

  // HTTP/1.1 with a Host header, as Prometheus sends it.
  const Reply ok11 =
      exchange(server->port(), "GET /metrics HTTP/1.1\r\nHost: x\r\nAccept: */*\r\n\r\n");
  EXPECT_NE(ok11.text.find(" 200 OK\r\n"), std::string::npos) << ok11.text;
  EXPECT_EQ(body_of(ok11.text), "# TYPE ddgi_sessions gauge\nddgi_sessions 3\n");

  for (const char* path : {"/", "/metrics/x", "/metricsx", "/other"}) {
    const Reply missing =
        exchange(server->port(), std::string("GET ") + path + " HTTP/1.0\r\n\r\n");
    EXPECT_NE(missing.text.find(" 404 Not Found\r\n"), std::string::npos) << path << missing.text;
    EXPECT_EQ(body_of(missing.text), "only /metrics is served here\n") << path;
  }
  const Reply post =
      exchange(server->port(), "POST /metrics HTTP/1.0\r\nContent-Length: 0\r\n\r\n");
  EXPECT_NE(post.text.find(" 400 Bad Request\r\n"), std::string::npos) << post.text;
  EXPECT_EQ(body_of(post.text), "expected GET /metrics\n");
}

// Issue 18: with one connection served at a time and a per-recv timeout of 2 s, a client
// sending a byte a second held the endpoint for as long as it liked, and a scrape waited.
TEST(MetricsHttpTest, SlowClientsDoNotDelayAScrape) {
  auto server = start_endpoint();
  ASSERT_NE(server, nullptr);
  constexpr int kSlowClients = 4;
  constexpr int kBytes = 8;  // at most ~8 s of trickling each
  std::vector<std::unique_ptr<SlowClient>> slow;
  for (int i = 0; i < kSlowClients; ++i) {
    slow.push_back(std::make_unique<SlowClient>(server->port(), kBytes, 1.0));
    ASSERT_TRUE(slow.back()->connected());
  }
  // Let the server accept them and start reading their first bytes.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  for (int attempt = 0; attempt < 3; ++attempt) {
    const Reply scrape = exchange(server->port(), "GET /metrics HTTP/1.0\r\n\r\n");
    // Bound: 500 ms for a loopback request on a loaded 2-core CI machine (measured ~1 ms).
    EXPECT_LT(scrape.seconds, 0.5)
        << "attempt " << attempt << ": the scrape took " << scrape.seconds << " s with "
        << kSlowClients << " slow clients connected";
    EXPECT_NE(scrape.text.find("ddgi_sessions 3"), std::string::npos) << scrape.text;
    std::cout << "scrape " << attempt << " with " << kSlowClients
              << " slow clients: " << scrape.seconds * 1000 << " ms\n";
  }
}

// A request whose header never completes is cut off at the per-request deadline, however
// steadily its bytes trickle in.
TEST(MetricsHttpTest, SlowClientIsCutOffAtTheRequestDeadline) {
  auto server = start_endpoint();
  ASSERT_NE(server, nullptr);
  // Half a byte a second for at most 12 s: longer than the deadline, each gap shorter than
  // any per-read timeout.
  SlowClient slow(server->port(), 24, 0.5);
  ASSERT_TRUE(slow.connected());
  slow.join();  // ends when the server closes the connection, or after the 24 bytes
  const double deadline = service::MetricsHttpServer::kRequestDeadlineSeconds;
  std::cout << "the server held the slow client for " << slow.held_seconds() << " s ("
            << slow.sent() << " bytes; deadline " << deadline << " s)\n";
  EXPECT_LT(slow.held_seconds(), deadline + 1.5)
      << "held " << slow.held_seconds() << " s, " << slow.sent() << " bytes sent";
}

}  // namespace
}  // namespace ddgi::test
