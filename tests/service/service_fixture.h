// Service tests run a real ddgi-server (server/service/server.h) in the test process on a
// loopback port, talking to it through the generated gRPC stubs like any client. The server
// shares one Vulkan context (lavapipe in CI) with validation on; a validation message during a
// test fails it. Scenes are tiny and fields small (2x2x2 probes, 16 rays) so runs stay fast.
#pragma once

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "ddgi/v1/render_service.grpc.pb.h"
#include "encode/image.h"
#include "service/server.h"
#include "vk/context.h"

namespace ddgi::test {

// GPU memory budget of the shared context: room for a few small sessions, far too little for
// the grid the budget test asks for.
inline constexpr uint64_t kTestGpuBudget = 256ull << 20;

// A new Vulkan context as the service tests use it: validation on, the test budget.
Result<std::unique_ptr<vk::Context>> create_service_context();
// The one the tests share (aborts when there is none).
vk::Context& service_context();

// A test server's options: small limits so every limit can be hit cheaply.
service::ServerOptions test_server_options();

class ServiceTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  // Tests override this to change limits, auth or TLS before the server starts.
  virtual void configure(service::ServerOptions&) {}
  // The Vulkan context the server runs on: the shared one, or a test's own (one it breaks).
  virtual vk::Context& vulkan() { return service_context(); }

  std::unique_ptr<grpc::ClientContext> context(double deadline_seconds = 60.0) const;
  // A session on cornell_box with the small test field; fails the test when it cannot.
  std::string create_session(const std::string& scene = "cornell_box", uint32_t warmup = 2);
  // CreateSession with `request`; fails the test (and returns an empty info) when it cannot.
  v1::SessionInfo create_session(const v1::CreateSessionRequest& request);
  v1::CreateSessionRequest small_session_request(const std::string& scene, uint32_t warmup) const;
  // The same in the shadow-field direct mode, with a small shadow field (3x3x3, 16 rays).
  v1::CreateSessionRequest small_shadow_field_session_request(const std::string& scene,
                                                              uint32_t warmup) const;
  // Appends name=value parameters to a request's list (field_params, shadow_field_params...).
  static void add_params(google::protobuf::RepeatedPtrField<v1::FieldParam>* list,
                         std::initializer_list<std::pair<const char*, const char*>> params);
  // SetFieldParams of one irradiance-field parameter.
  grpc::Status set_field_param(const std::string& session, const char* name, const char* value,
                               v1::FieldParams* reply);
  // A parameter's value as a FieldParams lists it; "(absent)" when it lists none of that name.
  static std::string param_value(const v1::FieldParams& field, const std::string& name);
  // RenderFrame of a one-off view.
  grpc::Status render(const std::string& session_id, uint32_t width, uint32_t height,
                      v1::Frame* frame, const v1::Camera* camera = nullptr);

  service::Server& server() { return *server_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(server_->port()); }

  std::string token_;  // sent with every call when non-empty
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::RenderService::Stub> stub_;

 private:
  std::unique_ptr<service::Server> server_;
  vk::Context* vulkan_ = nullptr;
  uint32_t validation_before_ = 0;
};

// Reads a stream on its own thread and counts frames, so tests can watch a client's frame rate
// while they do other things.
class StreamWatcher {
 public:
  // `keep_all`: keep every frame (all()), not only the newest.
  StreamWatcher(v1::RenderService::Stub& stub, v1::StreamFramesRequest request,
                const std::string& token = "", bool keep_all = false);
  ~StreamWatcher();  // cancels and joins
  uint64_t frames() const { return frames_.load(); }
  v1::Frame last() const;
  std::vector<v1::Frame> all() const;
  // Frames per second over the next `seconds`.
  double measure_fps(double seconds) const;
  // Waits until at least `count` frames arrived (false on timeout).
  bool wait_for(uint64_t count, double timeout_seconds) const;
  // Cancels the stream and returns how it ended.
  grpc::Status stop();
  // Waits for the server to end the stream (cancels after `timeout_seconds`); its status.
  grpc::Status wait_end(double timeout_seconds = 30.0);

 private:
  grpc::ClientContext context_;
  std::unique_ptr<grpc::ClientReader<v1::Frame>> reader_;
  std::atomic<uint64_t> frames_{0};
  std::atomic<bool> ended_{false};
  mutable std::mutex mutex_;
  v1::Frame last_;
  std::vector<v1::Frame> all_;  // with keep_all
  std::thread thread_;
  grpc::Status status_;
  bool stopped_ = false;
};

// Decoded JPEG of a frame.
encode::ImageRgba8 decode(const v1::Frame& frame);
// Mean of the RGB channels of an image, in [0, 255].
double mean_level(const encode::ImageRgba8& image);

// How long the slow-reader tests stall a client: 10 s, or DDGI_SLOW_READER_SECONDS (1..600)
// for quicker local runs.
double stall_seconds();
// Resident memory of this process (server and clients together), from /proc.
double resident_mib();

v1::Camera look_at(float px, float py, float pz, float tx, float ty, float tz, float fov = 40.0f);

}  // namespace ddgi::test
