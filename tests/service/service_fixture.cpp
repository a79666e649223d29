#include "tests/service/service_fixture.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "encode/jpeg.h"

namespace ddgi::test {

Result<std::unique_ptr<vk::Context>> create_service_context() {
  vk::ContextOptions options;
  options.validation = true;
  options.memory_budget_bytes = kTestGpuBudget;
  return vk::Context::create(options);
}

vk::Context& service_context() {
  static std::unique_ptr<vk::Context> context = [] {
    auto created = create_service_context();
    if (!created.ok()) {
      std::fprintf(stderr, "cannot create a Vulkan context: %s\n", created.error().message.c_str());
      std::abort();
    }
    return std::move(created).value();
  }();
  return *context;
}

service::ServerOptions test_server_options() {
  service::ServerOptions options;
  options.listen = "127.0.0.1:0";
  options.scene_root = DDGI_TEST_SCENE_ROOT;
  options.limits.max_sessions = 4;
  options.limits.max_views_per_session = 4;
  options.limits.max_width = 1024;
  options.limits.max_height = 1024;
  options.limits.max_message_bytes = 1 << 20;
  options.limits.max_upload_bytes = 256 << 10;
  options.limits.max_query_points = 1024;
  options.limits.max_fps = 30;
  options.limits.gpu_memory_budget_bytes = kTestGpuBudget;
  options.metrics_port = 0;
  options.metrics_address = "127.0.0.1";
  options.shutdown_grace = std::chrono::milliseconds(3000);
  return options;
}

void ServiceTest::SetUp() {
  vulkan_ = &vulkan();
  vk::Context& context = *vulkan_;
  validation_before_ = context.validation_message_count();
  service::ServerOptions options = test_server_options();
  configure(options);
  auto server = service::Server::start(context, options);
  ASSERT_TRUE(server.ok()) << server.error().message;
  server_ = std::move(server).value();
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  args.SetMaxSendMessageSize(64 << 20);
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  channel_ = grpc::CreateCustomChannel(address(), grpc::InsecureChannelCredentials(), args);
  stub_ = v1::RenderService::NewStub(channel_);
}

void ServiceTest::TearDown() {
  if (server_) {
    EXPECT_TRUE(server_->shutdown()) << "the server did not shut down in time";
  }
  server_.reset();
  if (!vulkan_) return;
  vk::Context& context = *vulkan_;
  context.collect_garbage();
  EXPECT_EQ(context.allocated_bytes(), 0u) << "GPU memory still held after every session closed";
  EXPECT_EQ(context.validation_message_count(), validation_before_)
      << "Vulkan validation reported problems during this test (see the log above)";
}

std::unique_ptr<grpc::ClientContext> ServiceTest::context(double deadline_seconds) const {
  auto context = std::make_unique<grpc::ClientContext>();
  context->set_deadline(std::chrono::system_clock::now() +
                        std::chrono::milliseconds(int64_t(deadline_seconds * 1000)));
  if (!token_.empty()) context->AddMetadata("authorization", "Bearer " + token_);
  return context;
}

v1::CreateSessionRequest ServiceTest::small_session_request(const std::string& scene,
                                                            uint32_t warmup) const {
  v1::CreateSessionRequest request;
  request.mutable_scene()->set_name(scene);
  request.set_warmup_updates(warmup);
  add_params(request.mutable_field_params(),
             {{"counts", "2,2,2"}, {"rays_per_probe", "16"}, {"fixed_rays", "8"}});
  return request;
}

v1::CreateSessionRequest ServiceTest::small_shadow_field_session_request(const std::string& scene,
                                                                         uint32_t warmup) const {
  v1::CreateSessionRequest request = small_session_request(scene, warmup);
  request.set_direct_mode(v1::DIRECT_MODE_SHADOW_FIELD);
  add_params(request.mutable_shadow_field_params(),
             {{"counts", "3,3,3"}, {"rays_per_probe", "16"}});
  return request;
}

void ServiceTest::add_params(google::protobuf::RepeatedPtrField<v1::FieldParam>* list,
                             std::initializer_list<std::pair<const char*, const char*>> params) {
  for (const auto& [name, value] : params) {
    v1::FieldParam* p = list->Add();
    p->set_name(name);
    p->set_value(value);
  }
}

grpc::Status ServiceTest::set_field_param(const std::string& session, const char* name,
                                          const char* value, v1::FieldParams* reply) {
  v1::SetFieldParamsRequest request;
  request.set_session_id(session);
  add_params(request.mutable_params(), {{name, value}});
  return stub_->SetFieldParams(context().get(), request, reply);
}

std::string ServiceTest::param_value(const v1::FieldParams& field, const std::string& name) {
  for (const v1::FieldParam& p : field.params()) {
    if (p.name() == name) return p.value();
  }
  return "(absent)";
}

v1::SessionInfo ServiceTest::create_session(const v1::CreateSessionRequest& request) {
  v1::SessionInfo info;
  auto ctx = context();
  const grpc::Status status = stub_->CreateSession(ctx.get(), request, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return status.ok() ? info : v1::SessionInfo{};
}

std::string ServiceTest::create_session(const std::string& scene, uint32_t warmup) {
  return create_session(small_session_request(scene, warmup)).session_id();
}

grpc::Status ServiceTest::render(const std::string& session_id, uint32_t width, uint32_t height,
                                 v1::Frame* frame, const v1::Camera* camera) {
  v1::RenderFrameRequest request;
  request.set_session_id(session_id);
  request.mutable_settings()->set_width(width);
  request.mutable_settings()->set_height(height);
  if (camera) *request.mutable_camera() = *camera;
  auto ctx = context();
  return stub_->RenderFrame(ctx.get(), request, frame);
}

StreamWatcher::StreamWatcher(v1::RenderService::Stub& stub, v1::StreamFramesRequest request,
                             const std::string& token, bool keep_all) {
  if (!token.empty()) context_.AddMetadata("authorization", "Bearer " + token);
  reader_ = stub.StreamFrames(&context_, request);
  thread_ = std::thread([this, keep_all] {
    v1::Frame frame;
    while (reader_->Read(&frame)) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        last_ = frame;
        if (keep_all) all_.push_back(frame);
      }
      frames_.fetch_add(1);
    }
    ended_ = true;
  });
}

std::vector<v1::Frame> StreamWatcher::all() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return all_;
}

StreamWatcher::~StreamWatcher() {
  (void)stop();
}

grpc::Status StreamWatcher::stop() {
  if (stopped_) return status_;
  stopped_ = true;
  context_.TryCancel();
  thread_.join();
  status_ = reader_->Finish();
  return status_;
}

grpc::Status StreamWatcher::wait_end(double timeout_seconds) {
  const auto end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  while (!ended_ && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (stopped_) return status_;
  stopped_ = true;
  if (!ended_) context_.TryCancel();
  thread_.join();
  status_ = reader_->Finish();
  return status_;
}

v1::Frame StreamWatcher::last() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_;
}

double StreamWatcher::measure_fps(double seconds) const {
  const uint64_t before = frames();
  const auto start = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return double(frames() - before) / elapsed;
}

bool StreamWatcher::wait_for(uint64_t count, double timeout_seconds) const {
  const auto end =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  while (frames() < count) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

encode::ImageRgba8 decode(const v1::Frame& frame) {
  const auto* data = reinterpret_cast<const uint8_t*>(frame.jpeg().data());
  auto image = encode::decode_jpeg({data, frame.jpeg().size()});
  EXPECT_TRUE(image.ok()) << (image.ok() ? "" : image.error().message);
  return image.ok() ? std::move(image).value() : encode::ImageRgba8{};
}

double mean_level(const encode::ImageRgba8& image) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i + 3 < image.pixels.size(); i += 4) {
    sum += image.pixels[i] + image.pixels[i + 1] + image.pixels[i + 2];
    count += 3;
  }
  return count ? sum / double(count) : 0.0;
}

double stall_seconds() {
  const char* text = std::getenv("DDGI_SLOW_READER_SECONDS");
  if (text == nullptr || *text == '\0') return 10.0;
  const double value = std::atof(text);
  return value >= 1.0 && value <= 600.0 ? value : 10.0;
}

double resident_mib() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

v1::Camera look_at(float px, float py, float pz, float tx, float ty, float tz, float fov) {
  v1::Camera camera;
  camera.mutable_position()->set_x(px);
  camera.mutable_position()->set_y(py);
  camera.mutable_position()->set_z(pz);
  camera.mutable_target()->set_x(tx);
  camera.mutable_target()->set_y(ty);
  camera.mutable_target()->set_z(tz);
  camera.set_vertical_fov_degrees(fov);
  return camera;
}

}  // namespace ddgi::test
