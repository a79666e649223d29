// End to end over loopback: sessions, views, camera, lights, instances, field parameters,
// frames (unary and streamed), atlases, queries, reflection and metrics.
#include <cmath>
#include <cstring>

#include "encode/jpeg.h"
#include "gi/field_params.h"
#include "gi/gi_stack.h"
#include "gi/irradiance_field.h"
#include "gi/shadow_params.h"
#include "gi/world_cache.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "shared/shadow_field_data.h"
#include "tests/service/atlas_download.h"
#include "tests/service/glb_builder.h"
#include "tests/service/reflection_probe.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

using E2eTest = ServiceTest;

// Waits (bounded) until the watcher's newest frame reflects command `seq`.
v1::Frame wait_for_command(const StreamWatcher& watcher, uint64_t seq, double timeout = 20.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  while (std::chrono::steady_clock::now() < end) {
    v1::Frame frame = watcher.last();
    if (frame.last_command_seq() >= seq && !frame.jpeg().empty()) return frame;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ADD_FAILURE() << "no frame showed command " << seq << " within " << timeout << " s";
  return {};
}

TEST_F(E2eTest, ServerInfoListsLibraryAndLimits) {
  v1::ServerInfo info;
  auto ctx = context();
  ASSERT_TRUE(stub_->GetServerInfo(ctx.get(), {}, &info).ok());
  EXPECT_FALSE(info.device_name().empty());
  EXPECT_TRUE(info.backend() == "query" || info.backend() == "pipeline");
  EXPECT_EQ(info.limits().max_sessions(), 4u);
  EXPECT_EQ(info.limits().max_upload_bytes(), 256u << 10);
  EXPECT_EQ(info.limits().gpu_memory_budget_bytes(), kTestGpuBudget);
  EXPECT_NE(std::find(info.scenes().begin(), info.scenes().end(), "cornell_box"),
            info.scenes().end());
  EXPECT_GT(info.field_params_size(), 10);
  EXPECT_FALSE(info.auth_required());
}

// The acceptance walk: load a scene, stream frames, move the camera, change and add lights;
// every change shows up in the first frame whose last_command_seq reaches the change's seq.
TEST_F(E2eTest, LoadMoveCameraChangeLightStream) {
  const std::string session = create_session();
  v1::StreamFramesRequest request;
  request.set_session_id(session);
  request.mutable_settings()->set_width(48);
  request.mutable_settings()->set_height(36);
  StreamWatcher watcher(*stub_, request);
  ASSERT_TRUE(watcher.wait_for(3, 30.0));
  const v1::Frame first = watcher.last();
  EXPECT_EQ(first.session_id(), session);
  EXPECT_FALSE(first.view_id().empty());
  EXPECT_EQ(first.width(), 48u);
  EXPECT_EQ(first.height(), 36u);
  EXPECT_GT(first.gpu_ms(), 0.0);
  EXPECT_GT(first.gi_update_ms(), 0.0);
  EXPECT_GT(first.passes_size(), 5);
  const double level_before = mean_level(decode(first));

  // Move the camera closer to the tall box.
  v1::SetCameraRequest move;
  move.set_session_id(session);
  move.set_view_id(first.view_id());
  *move.mutable_camera() = look_at(0.3f, 0.8f, 1.2f, 0.0f, 0.5f, 0.0f, 50.0f);
  v1::ViewInfo view;
  auto ctx = context();
  ASSERT_TRUE(stub_->SetCamera(ctx.get(), move, &view).ok());
  EXPECT_NEAR(view.camera().vertical_fov_degrees(), 50.0f, 1e-3f);
  const v1::Frame moved = wait_for_command(watcher, view.command_seq());
  EXPECT_NEAR(moved.camera().position().x(), 0.3f, 1e-5f);
  EXPECT_NEAR(moved.camera().position().z(), 1.2f, 1e-5f);
  EXPECT_GE(moved.last_command_arrival_unix_us(), first.last_command_arrival_unix_us());

  // Brighten the scene's light: the next frames are brighter.
  v1::UpdateLightRequest brighter;
  brighter.set_session_id(session);
  brighter.set_light_id(0);
  brighter.mutable_light()->set_intensity(12.0f);
  v1::LightReply light;
  ctx = context();
  ASSERT_TRUE(stub_->UpdateLight(ctx.get(), brighter, &light).ok());
  EXPECT_FLOAT_EQ(light.light().light().intensity(), 12.0f);
  EXPECT_EQ(light.light().light().name(), "ceiling_light");  // kept: partial update
  const double level_moved = mean_level(decode(moved));
  const v1::Frame lit = wait_for_command(watcher, light.command_seq());
  EXPECT_GT(mean_level(decode(lit)), level_moved + 5.0);

  // Add a second light, then remove it.
  v1::AddLightRequest add;
  add.set_session_id(session);
  add.mutable_light()->set_type(v1::LIGHT_TYPE_POINT);
  add.mutable_light()->set_intensity(2.0f);
  *add.mutable_light()->mutable_position() = look_at(0, 1.5f, 0.5f, 0, 0, 0).position();
  ctx = context();
  ASSERT_TRUE(stub_->AddLight(ctx.get(), add, &light).ok());
  EXPECT_EQ(light.light().light_id(), 1u);
  (void)wait_for_command(watcher, light.command_seq());
  v1::RemoveLightRequest remove;
  remove.set_session_id(session);
  remove.set_light_id(1);
  ctx = context();
  ASSERT_TRUE(stub_->RemoveLight(ctx.get(), remove, &light).ok());
  (void)wait_for_command(watcher, light.command_seq());

  v1::GetSessionRequest get;
  get.set_session_id(session);
  v1::SessionInfo info;
  ctx = context();
  ASSERT_TRUE(stub_->GetSession(ctx.get(), get, &info).ok());
  ASSERT_EQ(info.lights_size(), 1);
  EXPECT_FLOAT_EQ(info.lights(0).light().intensity(), 12.0f);
  EXPECT_EQ(info.views_size(), 1);  // the stream's own view
  EXPECT_GT(level_before, 1.0);
  EXPECT_TRUE(watcher.stop().error_code() == grpc::StatusCode::CANCELLED);
}

struct Difference {
  double mean_abs = 0.0;  // levels of 255, over R, G, B
  double psnr = 0.0;      // dB
};

Difference difference(const encode::ImageRgba8& a, const encode::ImageRgba8& b) {
  double abs_sum = 0.0, square_sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i) {
    if (i % 4 == 3) continue;  // alpha
    const double d = double(a.pixels[i]) - double(b.pixels[i]);
    abs_sum += std::abs(d);
    square_sum += d * d;
    ++count;
  }
  Difference out;
  out.mean_abs = abs_sum / double(std::max<size_t>(count, 1));
  out.psnr = 10.0 * std::log10(255.0 * 255.0 / std::max(square_sum / double(count), 1e-9));
  return out;
}

// The Renderer's image (what ddgi-render writes) of the default view of the Cornell box after
// `warmup` field updates and `frames` frames, each frame with one more update, as a session's
// loop records them.
encode::ImageRgba8 renderer_image(uint32_t warmup, uint64_t frames, uint32_t width,
                                  uint32_t height) {
  vk::Context& gpu = service_context();
  auto scene = load_scene(std::string(DDGI_TEST_SCENE_ROOT) + "/cornell_box.gltf");
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  auto options = fitted_gi_options(*scene, true, DirectMode::kTracedShadows,
                                   {"counts=2,2,2", "rays_per_probe=16", "fixed_rays=8"}, {},
                                   gpu.default_backend());
  EXPECT_TRUE(options.ok()) << options.error().message;
  auto gi = GiStack::create(gpu, *scene, *options);
  EXPECT_TRUE(gi.ok()) << gi.error().message;
  EXPECT_TRUE((*gi)->warm_up(warmup).ok());
  auto renderer = Renderer::create(gpu, (*gi)->scene(), (*gi)->field(), gpu.default_backend());
  EXPECT_TRUE(renderer.ok());
  FrameSettings settings;
  settings.width = width;
  settings.height = height;
  settings.camera = default_camera(*scene);
  encode::ImageRgba8 image;
  for (uint64_t f = 0; f < frames; ++f) {
    auto update = (*gi)->frame_update(settings.direct_mode, {});
    EXPECT_TRUE(update.ok()) << update.error().message;
    auto rendered = (*renderer)->render(settings, *update);
    EXPECT_TRUE(rendered.ok());
    image = {width, height, rendered->ldr};
  }
  return image;
}

// A frame from the service, streamed (StreamFrames) or unary (RenderFrame), is the Renderer's
// image of the same view (what ddgi-render writes) after as many field updates, up to JPEG.
// Each comes from a fresh session. The unary frame is the session's first (warm-up plus one
// update); a stream's first delivered frame may be the second, since two encoder threads may
// finish frame 2 first and a stream never sends an older frame after a newer one, so its
// reference is rendered for its own update count.
// Stated tolerance, at quality 95 (4:2:0) on this 64x48 Cornell box: mean absolute difference
// under 4.5 levels of 255 and PSNR above 30 dB against the Renderer's 8-bit image (JPEG's
// chroma subsampling of the red and green walls is most of it: measured 3.58 levels, 31.8 dB,
// streamed and unary alike), and under 0.5 levels against that image sent through the same
// JPEG encoder (measured 0: the service adds nothing but the encoding).
TEST_F(E2eTest, StreamedFrameMatchesRenderer) {
  constexpr uint32_t kWarmup = 3, kWidth = 64, kHeight = 48;
  v1::ViewSettings view_settings;
  view_settings.set_width(kWidth);
  view_settings.set_height(kHeight);
  view_settings.set_jpeg_quality(95);

  v1::StreamFramesRequest stream_request;
  stream_request.set_session_id(create_session("cornell_box", kWarmup));
  *stream_request.mutable_settings() = view_settings;
  v1::Frame streamed_frame;
  {
    grpc::ClientContext stream_context;
    auto reader = stub_->StreamFrames(&stream_context, stream_request);
    ASSERT_TRUE(reader->Read(&streamed_frame)) << "the stream delivered no frame";
    stream_context.TryCancel();
    (void)reader->Finish();
  }
  // One update per frame: the count and the frame index agree.
  ASSERT_GE(streamed_frame.frame_index(), 1u);
  ASSERT_LE(streamed_frame.frame_index(), 2u) << "the stream skipped more than one frame";
  EXPECT_EQ(streamed_frame.field_updates(), kWarmup + streamed_frame.frame_index());
  const encode::ImageRgba8 streamed = decode(streamed_frame);

  v1::RenderFrameRequest request;
  request.set_session_id(create_session("cornell_box", kWarmup));
  *request.mutable_settings() = view_settings;
  v1::Frame frame;
  auto ctx = context();
  ASSERT_TRUE(stub_->RenderFrame(ctx.get(), request, &frame).ok());
  EXPECT_EQ(frame.field_updates(), kWarmup + 1);
  const encode::ImageRgba8 served = decode(frame);

  struct Case {
    const char* name;
    const encode::ImageRgba8* image;
    uint64_t frames;
  };
  for (const Case& c :
       {Case{"streamed", &streamed, streamed_frame.frame_index()}, Case{"unary", &served, 1}}) {
    SCOPED_TRACE(c.name);
    const encode::ImageRgba8 reference = renderer_image(kWarmup, c.frames, kWidth, kHeight);
    // The reference through the same conversion (the service's GPU YUV planes equal the CPU's,
    // Yuv420Test) and encoder: what JPEG alone changes.
    auto jpeg = encode::encode_jpeg(encode::to_yuv420(reference), 95);
    ASSERT_TRUE(jpeg.ok());
    auto round_trip = encode::decode_jpeg(*jpeg);
    ASSERT_TRUE(round_trip.ok());
    ASSERT_EQ(c.image->width, kWidth);
    ASSERT_EQ(c.image->height, kHeight);
    const Difference vs_reference = difference(*c.image, reference);
    const Difference vs_round_trip = difference(*c.image, *round_trip);
    std::printf(
        "%s frame (%llu) vs Renderer: mean |d| %.3f levels, PSNR %.2f dB; vs the Renderer image "
        "through JPEG: mean |d| %.3f\n",
        c.name, static_cast<unsigned long long>(c.frames), vs_reference.mean_abs, vs_reference.psnr,
        vs_round_trip.mean_abs);
    EXPECT_LT(vs_reference.mean_abs, 4.5);
    EXPECT_GT(vs_reference.psnr, 30.0);
    EXPECT_LT(vs_round_trip.mean_abs, 0.5);
  }
}

TEST_F(E2eTest, FieldParamsTakeEffectAndAreReported) {
  const std::string session = create_session();
  v1::GetFieldParamsRequest get;
  get.set_session_id(session);
  v1::FieldParams before;
  auto ctx = context();
  ASSERT_TRUE(stub_->GetFieldParams(ctx.get(), get, &before).ok());
  EXPECT_EQ(before.probes(), 8u);
  auto value_of = [](const v1::FieldParams& params, const std::string& name) {
    for (const auto& p : params.params()) {
      if (p.name() == name) return p.value();
    }
    return std::string("<absent>");
  };
  EXPECT_EQ(value_of(before, "counts"), "2,2,2");

  v1::SetFieldParamsRequest set;
  set.set_session_id(session);
  for (auto [name, value] : {std::pair{"counts", "3,2,2"}, {"hysteresis", "0.5"}}) {
    auto* p = set.add_params();
    p->set_name(name);
    p->set_value(value);
  }
  v1::FieldParams after;
  ctx = context();
  ASSERT_TRUE(stub_->SetFieldParams(ctx.get(), set, &after).ok());
  EXPECT_EQ(after.probes(), 12u);
  EXPECT_EQ(value_of(after, "counts"), "3,2,2");
  EXPECT_EQ(value_of(after, "hysteresis"), "0.5");
  EXPECT_EQ(value_of(after, "rays_per_probe"), "16");  // untouched: partial update
  EXPECT_GT(after.gpu_bytes(), before.gpu_bytes());
  EXPECT_EQ(after.params_size(), before.params_size());

  // The new grid is what frames are rendered with: they still come, GI included.
  v1::Frame frame;
  ASSERT_TRUE(render(session, 32, 24, &frame).ok());
  EXPECT_GT(frame.gi_update_ms(), 0.0);
  v1::DumpAtlasRequest dump;
  dump.set_session_id(session);
  dump.set_kind(v1::ATLAS_KIND_IRRADIANCE);
  dump.set_format(v1::ATLAS_FORMAT_RAW_F32);
  ctx = context();
  auto reader = stub_->DumpAtlas(ctx.get(), dump);
  v1::AtlasChunk chunk;
  ASSERT_TRUE(reader->Read(&chunk));
  EXPECT_EQ(chunk.metadata().probe_counts_x(), 3);
  while (reader->Read(&chunk)) {
  }
  EXPECT_TRUE(reader->Finish().ok());
}

TEST_F(E2eTest, InstanceTransformMovesObject) {
  const std::string session = create_session();
  v1::Frame before, after;
  ASSERT_TRUE(render(session, 48, 36, &before).ok());
  v1::SetInstanceTransformRequest move;
  move.set_session_id(session);
  move.set_instance_index(6);  // tall_box
  const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.4f, 0.0f, 0.3f, 1};
  for (float v : m) move.mutable_transform()->add_m(v);
  v1::InstanceReply reply;
  auto ctx = context();
  ASSERT_TRUE(stub_->SetInstanceTransform(ctx.get(), move, &reply).ok());
  EXPECT_EQ(reply.instance().name(), "tall_box");
  EXPECT_FLOAT_EQ(reply.instance().transform().m(12), 0.4f);
  ASSERT_TRUE(render(session, 48, 36, &after).ok());
  EXPECT_GE(after.last_command_seq(), reply.command_seq());
  const auto a = decode(before), b = decode(after);
  double difference = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) difference += std::abs(a.pixels[i] - b.pixels[i]);
  EXPECT_GT(difference / double(a.pixels.size()), 1.0);
}

TEST_F(E2eTest, UploadedGlbSession) {
  v1::CreateSessionRequest request;
  request.mutable_scene()->set_glb(make_floor_glb());
  request.set_warmup_updates(1);
  v1::SessionInfo info;
  auto ctx = context();
  const grpc::Status status = stub_->CreateSession(ctx.get(), request, &info);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(info.triangles(), 2u);
  EXPECT_EQ(info.scene().rfind("upload:", 0), 0u);
  ASSERT_EQ(info.lights_size(), 1);
  v1::Frame frame;
  ASSERT_TRUE(render(info.session_id(), 32, 24, &frame).ok());
  EXPECT_GT(mean_level(decode(frame)), 1.0);
}

TEST_F(E2eTest, LoadSceneReplacesScene) {
  const std::string session = create_session();
  v1::LoadSceneRequest load;
  load.set_session_id(session);
  load.mutable_scene()->set_name("box_on_floor");
  load.set_warmup_updates(1);
  v1::SessionInfo info;
  auto ctx = context();
  const grpc::Status status = stub_->LoadScene(ctx.get(), load, &info);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(info.scene(), "box_on_floor");
  EXPECT_EQ(info.session_id(), session);
  v1::Frame frame;
  ASSERT_TRUE(render(session, 32, 24, &frame).ok());
}

TEST_F(E2eTest, AtlasDumpExrAndRaw) {
  const std::string session = create_session();
  for (auto format : {v1::ATLAS_FORMAT_EXR, v1::ATLAS_FORMAT_RAW_F32}) {
    for (auto kind : {v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_KIND_DISTANCE}) {
      v1::DumpAtlasRequest request;
      request.set_session_id(session);
      request.set_kind(kind);
      request.set_format(format);
      auto ctx = context();
      auto reader = stub_->DumpAtlas(ctx.get(), request);
      v1::AtlasChunk chunk;
      ASSERT_TRUE(reader->Read(&chunk));
      ASSERT_TRUE(chunk.has_metadata());
      const v1::AtlasMetadata metadata = chunk.metadata();
      std::string bytes;
      while (reader->Read(&chunk)) {
        EXPECT_EQ(chunk.offset(), bytes.size());
        EXPECT_LE(chunk.ByteSizeLong(), 1u << 20);  // the test server's message limit
        bytes += chunk.data();
      }
      ASSERT_TRUE(reader->Finish().ok());
      EXPECT_EQ(bytes.size(), metadata.total_bytes());
      const uint32_t channels = kind == v1::ATLAS_KIND_IRRADIANCE ? 4 : 2;
      EXPECT_EQ(metadata.channels_size(), int(channels));
      EXPECT_EQ(metadata.probe_counts_x() * metadata.probe_counts_y() * metadata.probe_counts_z(),
                8);
      EXPECT_EQ(metadata.border_texels(), 1u);
      // 2x2x2 probes: 3 tiles per row, 3 rows of (texels + 2) texels.
      EXPECT_EQ(metadata.width(), 3 * (metadata.texels_per_probe() + 2));
      if (format == v1::ATLAS_FORMAT_RAW_F32) {
        EXPECT_EQ(bytes.size(), size_t(metadata.width()) * metadata.height() * channels * 4);
      } else {
        EXPECT_EQ(bytes.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));  // EXR magic
      }
    }
  }
  // Probe states: one texel per probe.
  v1::DumpAtlasRequest states;
  states.set_session_id(session);
  states.set_kind(v1::ATLAS_KIND_PROBE_STATES);
  states.set_format(v1::ATLAS_FORMAT_RAW_F32);
  auto ctx = context();
  auto reader = stub_->DumpAtlas(ctx.get(), states);
  v1::AtlasChunk chunk;
  ASSERT_TRUE(reader->Read(&chunk));
  EXPECT_EQ(chunk.metadata().width(), 2u);
  EXPECT_EQ(chunk.metadata().height(), 4u);
  EXPECT_EQ(chunk.metadata().channels(3), "state");
  EXPECT_EQ(chunk.metadata().total_bytes(), 8u * 4u * 4u);
  while (reader->Read(&chunk)) {
  }
  EXPECT_TRUE(reader->Finish().ok());
  // This session has no shadow field.
  v1::DumpAtlasRequest shadow;
  shadow.set_session_id(session);
  shadow.set_kind(v1::ATLAS_KIND_SHADOW);
  ctx = context();
  reader = stub_->DumpAtlas(ctx.get(), shadow);
  EXPECT_FALSE(reader->Read(&chunk));
  const grpc::Status status = reader->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(status.error_message().find("has no shadow field"), std::string::npos)
      << status.error_message();
}

// A session in the world cache's AO mode (GI off, box_on_floor): GetSession has no cache before
// the first frame; after frames it reports the table (capacity, live entries, its bytes, which
// the session's GPU bytes include), and the frames carry the cache's passes.
TEST_F(E2eTest, AoCacheSessionReportsItsCache) {
  v1::CreateSessionRequest request = small_session_request("box_on_floor", 2);
  request.set_gi(false);
  request.set_direct_mode(v1::DIRECT_MODE_AO_CACHE);
  const v1::SessionInfo created = create_session(request);
  ASSERT_FALSE(created.session_id().empty());
  EXPECT_FALSE(created.has_world_cache());
  v1::Frame frame;
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(render(created.session_id(), 48, 36, &frame).ok());
  bool cache_pass = false;
  for (const auto& pass : frame.passes()) cache_pass |= pass.name() == "cache resolve";
  EXPECT_TRUE(cache_pass) << "no cache resolve pass in the frame";
  v1::GetSessionRequest get;
  get.set_session_id(created.session_id());
  v1::SessionInfo info;
  auto ctx = context();
  ASSERT_TRUE(stub_->GetSession(ctx.get(), get, &info).ok());
  ASSERT_TRUE(info.has_world_cache());
  const v1::WorldCacheInfo& cache = info.world_cache();
  std::printf("ao-cache session: %u of %u entries live, %llu bytes of the session's %llu\n",
              cache.occupied(), cache.capacity(),
              static_cast<unsigned long long>(cache.gpu_bytes()),
              static_cast<unsigned long long>(info.gpu_bytes()));
  EXPECT_EQ(cache.capacity(), WorldCacheParams{}.entries);
  EXPECT_GT(cache.occupied(), 0u);
  EXPECT_LE(cache.occupied(), cache.capacity());
  EXPECT_EQ(cache.gpu_bytes(), world_cache_bytes(WorldCacheParams{}));
  EXPECT_GE(info.gpu_bytes(), created.gpu_bytes() + cache.gpu_bytes());
  // The metrics count the same live entries (every frame was read back before GetSession), and
  // take them off when the session closes.
  EXPECT_EQ(server().metrics().world_cache_entries.load(), int64_t(cache.occupied()));
  EXPECT_EQ(server().metrics().world_cache_inserted.load(), uint64_t(cache.inserted()));
  v1::CloseSessionRequest close;
  close.set_session_id(created.session_id());
  v1::CloseSessionReply closed;
  auto close_ctx = context();
  ASSERT_TRUE(stub_->CloseSession(close_ctx.get(), close, &closed).ok());
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (server().metrics().sessions.load() != 0 && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(server().metrics().world_cache_entries.load(), 0);
}

// A session in the shadow-field direct mode: frames include the shadow field's update, its
// parameters are read and changed through the same RPCs with field=SHADOW, its atlases dump.
TEST_F(E2eTest, ShadowFieldSession) {
  const v1::SessionInfo info = create_session(small_shadow_field_session_request("cornell_box", 2));
  ASSERT_FALSE(info.session_id().empty());
  v1::Frame frame;
  ASSERT_TRUE(render(info.session_id(), 32, 24, &frame).ok());
  bool shadow_pass = false;
  for (const auto& pass : frame.passes()) shadow_pass |= pass.name().rfind("shadow ", 0) == 0;
  EXPECT_TRUE(shadow_pass) << "no shadow-field pass in the frame";
  EXPECT_GT(mean_level(decode(frame)), 1.0);

  v1::SetFieldParamsRequest set;
  set.set_session_id(info.session_id());
  set.set_field(v1::FIELD_KIND_SHADOW);
  add_params(set.mutable_params(), {{"hysteresis", "0.5"}});
  v1::FieldParams params;
  auto ctx = context();
  ASSERT_TRUE(stub_->SetFieldParams(ctx.get(), set, &params).ok());
  EXPECT_EQ(params.field(), v1::FIELD_KIND_SHADOW);
  EXPECT_EQ(params.probes(), 27u);
  bool found = false;
  for (const auto& param : params.params()) {
    if (param.name() == "hysteresis") {
      found = true;
      EXPECT_EQ(param.value(), "0.5");
    }
  }
  EXPECT_TRUE(found);

  // The atlas size follows from the session's parameters alone: 3x3x3 probes tile
  // ceil(sqrt(27)) = 6 per row in 5 rows, each tile the default interior plus a border on both
  // sides, one band of 4 channels (the default max_lights = 4 fits one group of 4).
  const uint32_t tile = ShadowFieldParams{}.texels + 2 * gpu::kShadowAtlasBorder;
  const uint64_t raw_bytes = uint64_t(6 * tile) * (5 * tile) * 4 * sizeof(float);
  for (auto kind : {v1::ATLAS_KIND_SHADOW, v1::ATLAS_KIND_SHADOW_MOMENTS}) {
    for (auto format : {v1::ATLAS_FORMAT_RAW_F32, v1::ATLAS_FORMAT_EXR}) {
      SCOPED_TRACE(v1::AtlasKind_Name(kind) + " " + v1::AtlasFormat_Name(format));
      const AtlasDownload dump = download_atlas(*stub_, info.session_id(), kind, format);
      ASSERT_TRUE(dump.status.ok()) << dump.status.error_message();
      EXPECT_EQ(dump.metadata.probe_counts_x(), 3);
      EXPECT_EQ(dump.metadata.channels_size(), 4);
      EXPECT_EQ(dump.metadata.width(), 6 * tile);
      EXPECT_EQ(dump.metadata.height(), 5 * tile);
      // The data chunks carry exactly the bytes the metadata announced...
      EXPECT_EQ(dump.bytes.size(), dump.metadata.total_bytes());
      // ...and raw float32 texels are exactly the atlas computed above (a compressed EXR's size
      // is not predictable, only non-empty).
      if (format == v1::ATLAS_FORMAT_RAW_F32) {
        EXPECT_EQ(dump.bytes.size(), raw_bytes);
      } else {
        EXPECT_GT(dump.bytes.size(), 0u);
      }
    }
  }
}

TEST_F(E2eTest, QueryIrradianceBatch) {
  const std::string session = create_session("cornell_box", 8);
  v1::QueryIrradianceRequest request;
  request.set_session_id(session);
  for (int i = 0; i < 10; ++i) {
    auto* p = request.add_points();
    p->mutable_position()->set_x(-0.4f + 0.08f * float(i));
    p->mutable_position()->set_y(0.05f);
    p->mutable_normal()->set_y(1.0f);
  }
  v1::QueryIrradianceReply reply;
  auto ctx = context();
  ASSERT_TRUE(stub_->QueryIrradiance(ctx.get(), request, &reply).ok());
  ASSERT_EQ(reply.irradiance_size(), 10);
  for (const auto& e : reply.irradiance()) {
    EXPECT_TRUE(std::isfinite(e.x()) && e.x() >= 0.0f);
  }
  EXPECT_GT(reply.irradiance(5).x(), 0.0f);  // the floor under the light receives something
  EXPECT_GE(reply.field_updates(), 8u);
}

TEST_F(E2eTest, ViewsAndSessionsLifecycle) {
  const std::string session = create_session();
  v1::CreateViewRequest create;
  create.set_session_id(session);
  create.mutable_settings()->set_width(40);
  create.mutable_settings()->set_height(30);
  v1::ViewInfo view;
  auto ctx = context();
  ASSERT_TRUE(stub_->CreateView(ctx.get(), create, &view).ok());
  EXPECT_EQ(view.settings().width(), 40u);
  EXPECT_EQ(view.settings().jpeg_quality(), 85u);

  v1::UpdateViewRequest update;
  update.set_session_id(session);
  update.set_view_id(view.view_id());
  update.mutable_settings()->set_exposure(2.0f);
  ctx = context();
  ASSERT_TRUE(stub_->UpdateView(ctx.get(), update, &view).ok());
  EXPECT_FLOAT_EQ(view.settings().exposure(), 2.0f);
  EXPECT_EQ(view.settings().width(), 40u);

  v1::RenderFrameRequest frame_request;
  frame_request.set_session_id(session);
  frame_request.set_view_id(view.view_id());
  v1::Frame frame;
  ctx = context();
  ASSERT_TRUE(stub_->RenderFrame(ctx.get(), frame_request, &frame).ok());
  EXPECT_EQ(frame.width(), 40u);
  EXPECT_EQ(frame.view_id(), view.view_id());

  v1::ListSessionsReply list;
  ctx = context();
  ASSERT_TRUE(stub_->ListSessions(ctx.get(), {}, &list).ok());
  ASSERT_EQ(list.sessions_size(), 1);
  EXPECT_EQ(list.sessions(0).views(), 1u);

  v1::DeleteViewRequest remove;
  remove.set_session_id(session);
  remove.set_view_id(view.view_id());
  v1::DeleteViewReply removed;
  ctx = context();
  ASSERT_TRUE(stub_->DeleteView(ctx.get(), remove, &removed).ok());
  ctx = context();
  const grpc::Status gone = stub_->RenderFrame(ctx.get(), frame_request, &frame);
  EXPECT_EQ(gone.error_code(), grpc::StatusCode::NOT_FOUND);

  v1::CloseSessionRequest close;
  close.set_session_id(session);
  v1::CloseSessionReply closed;
  ctx = context();
  ASSERT_TRUE(stub_->CloseSession(ctx.get(), close, &closed).ok());
  service_context().collect_garbage();
  EXPECT_EQ(service_context().allocated_bytes(), 0u);
  ctx = context();
  ASSERT_TRUE(stub_->ListSessions(ctx.get(), {}, &list).ok());
  EXPECT_EQ(list.sessions_size(), 0);
}

// A client that disconnects mid-stream leaves nothing behind: the stream and its view go, and
// closing the session returns every byte of GPU memory.
TEST_F(E2eTest, DisconnectMidStreamLeavesNoLeak) {
  const std::string session = create_session();
  for (int round = 0; round < 3; ++round) {
    v1::StreamFramesRequest request;
    request.set_session_id(session);
    request.mutable_settings()->set_width(32);
    request.mutable_settings()->set_height(24);
    auto watcher = std::make_unique<StreamWatcher>(*stub_, request);
    ASSERT_TRUE(watcher->wait_for(2, 30.0));
    watcher.reset();  // cancels mid-stream, like a client that went away
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (server().metrics().streams.load() != 0 && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(server().metrics().streams.load(), 0);
  v1::GetSessionRequest get;
  get.set_session_id(session);
  v1::SessionInfo info;
  auto ctx = context();
  ASSERT_TRUE(stub_->GetSession(ctx.get(), get, &info).ok());
  EXPECT_EQ(info.views_size(), 0) << "the streams' views outlived them";
  EXPECT_EQ(server().metrics().views.load(), 0);

  v1::CloseSessionRequest close;
  close.set_session_id(session);
  v1::CloseSessionReply closed;
  ctx = context();
  ASSERT_TRUE(stub_->CloseSession(ctx.get(), close, &closed).ok());
  service_context().collect_garbage();
  EXPECT_EQ(service_context().allocated_bytes(), 0u);
  EXPECT_EQ(server().metrics().sessions.load(), 0);
}

// Reflection answers list_services (off with --no-reflection: ServiceLimitsProcessTest).
TEST_F(E2eTest, ReflectionListsServices) {
  const ReflectionAnswer answer = list_services(channel_);
  ASSERT_TRUE(answer.status.ok()) << answer.status.error_message();
  EXPECT_NE(answer.text.find("ddgi.v1.RenderService"), std::string::npos);
  EXPECT_NE(answer.text.find("grpc.health.v1.Health"), std::string::npos);
}

TEST_F(E2eTest, MetricsEndpointServesPrometheusText) {
  const std::string session = create_session();
  v1::Frame frame;
  ASSERT_TRUE(render(session, 32, 24, &frame).ok());
  const int port = server().metrics_port();
  ASSERT_GT(port, 0);
  // A plain HTTP/1.0 GET over a socket.
  const std::string command = "exec 3<>/dev/tcp/127.0.0.1/" + std::to_string(port) +
                              "; printf 'GET /metrics HTTP/1.0\\r\\n\\r\\n' >&3; cat <&3";
  FILE* pipe = popen(("bash -c \"" + command + "\"").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string body;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof(buffer), pipe)) body.append(buffer, n);
  pclose(pipe);
  EXPECT_EQ(body.rfind("HTTP/1.1 200 OK", 0), 0u) << body.substr(0, 200);
  for (const char* name :
       {"ddgi_sessions 1", "ddgi_frames_rendered_total", "ddgi_frames_dropped_total",
        "ddgi_frame_seconds_bucket", "ddgi_gi_update_seconds_count", "ddgi_encode_seconds_sum",
        "ddgi_gpu_memory_bytes", "ddgi_rpcs_total{method=\"RenderFrame\",code=\"OK\"} 1"}) {
    EXPECT_NE(body.find(name), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace ddgi::test
