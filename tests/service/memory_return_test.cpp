// Memory comes back after sessions close. Each session loads its scene on its own frame-loop
// thread, so glibc gives every one a malloc arena of its own; what those arenas keep after the
// session is gone stayed resident (issue 18: ~1 GiB after a few scene loads, all sessions
// closed). The server process is this test process: its VmRSS is read from /proc/self/status,
// with malloc set up as ddgi-server's main sets it (the same arena cap).
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "service/process_memory.h"
#include "tests/service/glb_builder.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

constexpr uint32_t kCells = 400;  // 320000 triangles, a 5.8 MB upload
constexpr int kSessions = 3;      // at once, each on its own thread
constexpr int kRounds = 3;
// Tolerance for what stays resident after every session closed: 64 MiB over the baseline.
// Measured on lavapipe: +8 to +19 MiB; +185 to +193 MiB with the session loop's malloc_trim
// taken out; the growth was ~1 GiB.
constexpr double kToleranceMiB = 64.0;

double rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // kB
  }
  return -1.0;
}

class MemoryReturnTest : public ServiceTest {
 protected:
  void SetUp() override {
    // Before the server's threads start, as in ddgi-server's main. Without the cap (up to 8
    // arenas per core), freed fragments in more arenas made the residue vary from run to run:
    // +33 to +69 MiB after three rounds over a one-session baseline, over the tolerance in one CI
    // run.
    service::limit_malloc_arenas(service::kServerMallocArenas);
    ServiceTest::SetUp();
  }
  void configure(service::ServerOptions& options) override {
    options.limits.max_upload_bytes = 16 << 20;
    options.limits.max_sessions = kSessions;
  }

  std::string create_upload_session(const std::string& glb) {
    v1::CreateSessionRequest request = small_session_request("cornell_box", 1);
    request.mutable_scene()->set_glb(glb);
    v1::SessionInfo info;
    auto ctx = context(120.0);
    const grpc::Status status = stub_->CreateSession(ctx.get(), request, &info);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return info.session_id();
  }

  void close_session(const std::string& id) {
    v1::CloseSessionRequest request;
    request.set_session_id(id);
    v1::CloseSessionReply reply;
    auto ctx = context();
    EXPECT_TRUE(stub_->CloseSession(ctx.get(), request, &reply).ok()) << id;
  }

  // kSessions uploads loaded at once, then closed; returns the resident memory at their peak.
  double serve_one_round(const std::string& glb) {
    std::vector<std::string> ids(kSessions);
    std::vector<std::thread> threads;
    for (int i = 0; i < kSessions; ++i) {
      threads.emplace_back([&, i] { ids[size_t(i)] = create_upload_session(glb); });
    }
    for (std::thread& t : threads) t.join();
    const double peak = rss_mib();
    for (const std::string& id : ids) {
      if (!id.empty()) close_session(id);
    }
    EXPECT_TRUE(server().sessions().wait_for_loops(std::chrono::seconds(30)));
    return peak;
  }
};

TEST_F(MemoryReturnTest, RssReturnsNearBaselineAfterSessionsClose) {
  const std::string glb = make_grid_glb(kCells);
  // The first round compiles the pipelines and fills the driver's and gRPC's caches for
  // kSessions at once; with its free memory handed back, what stays is the baseline: a server
  // that has served once. (A baseline after one session left those caches' ~25 MiB of live
  // heap to the tolerance.)
  double peak = serve_one_round(glb);
  service::release_free_memory();
  const double baseline = rss_mib();
  for (int round = 0; round < kRounds; ++round) peak = std::max(peak, serve_one_round(glb));
  const double after = rss_mib();
  std::cout << "VmRSS: baseline " << baseline << " MiB, peak " << peak << " MiB with " << kSessions
            << " sessions of " << glb.size() << " bytes, after " << kRounds
            << " rounds and every session closed " << after << " MiB (+" << after - baseline
            << " MiB; tolerance " << kToleranceMiB << " MiB)\n";
  EXPECT_LT(after - baseline, kToleranceMiB)
      << "baseline " << baseline << " MiB, peak " << peak << " MiB, after " << after << " MiB";
}

}  // namespace
}  // namespace ddgi::test
