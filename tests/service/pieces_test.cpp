// The service's pure pieces, without a server: scene-name checks and the library listing,
// wire-value validation, metrics text, and the escaping of client text in messages.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "service/convert.h"
#include "service/frame_stream.h"
#include "service/limits.h"
#include "service/metrics.h"
#include "service/scene_library.h"
#include "service/text.h"

namespace ddgi::test {
namespace {

using service::SceneLibrary;

TEST(SceneLibraryTest, ListsStemsAndResolvesOnlyListedNames) {
  const std::filesystem::path root =
      std::filesystem::path(testing::TempDir()) / ("ddgi_library_" + std::to_string(::getpid()));
  std::filesystem::create_directories(root / "sub");
  for (const char* name : {"a.gltf", "a.ddgi.json", "b.glb", "c.ddgi.json", "notes.txt",
                           ".hidden.gltf", "sub/d.gltf"}) {
    std::ofstream(root / name) << "x";
  }
  const SceneLibrary library(root.string());
  EXPECT_EQ(library.names(), (std::vector<std::string>{"a", "b", "c"}));
  auto a = library.resolve("a");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(std::filesystem::path(*a).filename(), "a.gltf");  // the glTF, not its sidecar
  EXPECT_EQ(library.resolve("d").error().code, ErrorCode::kNotFound);
  EXPECT_EQ(library.resolve("notes").error().code, ErrorCode::kNotFound);
  EXPECT_EQ(library.resolve("sub/d").error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(library.resolve(".hidden").error().code, ErrorCode::kInvalidArgument);
  std::filesystem::remove_all(root);
}

TEST(SceneLibraryTest, NameForms) {
  for (const char* good : {"cornell_box", "a-b.c", "X1"}) {
    EXPECT_TRUE(service::validate_scene_name(good).ok()) << good;
  }
  for (const std::string& bad :
       {std::string("../x"), std::string("/abs"), std::string("a\\b"), std::string("a..b"),
        std::string("a\0b", 3), std::string(""), std::string("a b"), std::string(129, 'a')}) {
    EXPECT_EQ(service::validate_scene_name(bad).error().code, ErrorCode::kInvalidArgument);
  }
}

TEST(ConvertTest, CameraIsNormalizedAndChecked) {
  v1::Camera in;
  in.mutable_position()->set_z(2.0f);
  in.mutable_forward()->set_z(-5.0f);
  in.mutable_up()->set_y(2.0f);
  in.mutable_up()->set_z(1.0f);  // not orthogonal: the server fixes it
  auto camera = service::camera_from_proto(in, Camera{});
  ASSERT_TRUE(camera.ok());
  EXPECT_NEAR(glm::length(camera->forward), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(camera->forward, camera->up), 0.0f, 1e-6f);
  EXPECT_NEAR(camera->yfov, 45.0f * 3.14159265f / 180.0f, 1e-6f);  // 0 means 45 degrees
  in.mutable_up()->set_y(0.0f);
  in.mutable_up()->set_z(1.0f);  // parallel to forward
  EXPECT_NE(service::camera_from_proto(in, Camera{}).error().message.find("parallel"),
            std::string::npos);
  v1::Camera no_aim;
  EXPECT_NE(
      service::camera_from_proto(no_aim, Camera{}).error().message.find("target or a forward"),
      std::string::npos);
}

TEST(ConvertTest, LightPartialUpdateKeepsOtherValues) {
  Light base;
  base.name = "key";
  base.intensity = 3.0f;
  v1::Light change;
  change.mutable_color()->set_x(0.5f);
  change.mutable_color()->set_y(0.5f);
  change.mutable_color()->set_z(0.5f);
  auto light = service::light_from_proto(change, base);
  ASSERT_TRUE(light.ok());
  EXPECT_EQ(light->name, "key");
  EXPECT_FLOAT_EQ(light->intensity, 3.0f);
  EXPECT_FLOAT_EQ(light->color.x, 0.5f);
  change.set_range(std::numeric_limits<float>::quiet_NaN());
  EXPECT_EQ(service::light_from_proto(change, base).error().message,
            "light.range must be finite and in [0, 1e9] (got nan)");
}

TEST(ConvertTest, ViewSettingsAllOrNothing) {
  service::ServiceLimits limits;
  service::ViewConfig config;
  v1::ViewSettings settings;
  settings.set_width(320);
  settings.set_jpeg_quality(0);  // bad: nothing may change
  EXPECT_FALSE(service::apply_view_settings(settings, limits, config).ok());
  EXPECT_EQ(config.width, 640u);
  settings.set_jpeg_quality(50);
  ASSERT_TRUE(service::apply_view_settings(settings, limits, config).ok());
  EXPECT_EQ(config.width, 320u);
  EXPECT_EQ(config.height, 480u);
}

TEST(LimitsTest, RangesAndReceiveSize) {
  service::ServiceLimits limits;
  EXPECT_TRUE(service::validate(limits).ok());
  EXPECT_EQ(service::max_receive_bytes(limits), limits.max_upload_bytes + (64u << 10));
  limits.max_sessions = 0;
  EXPECT_NE(service::validate(limits).error().message.find("--max-sessions"), std::string::npos);
}

TEST(MetricsTest, PrometheusTextFormat) {
  service::Metrics metrics;
  metrics.frames_dropped += 3;
  metrics.encode_seconds.observe(0.003);
  metrics.encode_seconds.observe(100.0);
  metrics.count_rpc("SetCamera", "OK");
  metrics.add_gauge("ddgi_test_gauge", "A test.", [] { return 7.0; });
  const std::string text = metrics.prometheus_text();
  EXPECT_NE(text.find("# TYPE ddgi_frames_dropped_total counter\nddgi_frames_dropped_total 3\n"),
            std::string::npos);
  EXPECT_NE(text.find("ddgi_encode_seconds_bucket{le=\"0.004\"} 1\n"), std::string::npos);
  EXPECT_NE(text.find("ddgi_encode_seconds_bucket{le=\"+Inf\"} 2\n"), std::string::npos);
  EXPECT_NE(text.find("ddgi_encode_seconds_count 2\n"), std::string::npos);
  EXPECT_NE(text.find("ddgi_rpcs_total{method=\"SetCamera\",code=\"OK\"} 1\n"), std::string::npos);
  EXPECT_NE(text.find("ddgi_test_gauge 7\n"), std::string::npos);
}

std::shared_ptr<const v1::Frame> frame_with_index(uint64_t index) {
  auto frame = std::make_shared<v1::Frame>();
  frame->set_frame_index(index);
  return frame;
}

// A stream counts a frame as dropped when a newer one reaches it, not when the encoder drops it:
// the frame before the gap must not carry the drop (the CI failure of 2026-12-05: frame 28 said
// one more drop than 27 with no index between them, frame 30 one less than the gap 28 -> 30).
// A frame that finishes after a newer one was sent is dropped once, not twice.
TEST(FrameStreamTest, DropsCountWhenTheNextFrameArrives) {
  service::Metrics metrics;
  service::FrameStreamState stream(metrics, 0.0);
  for (uint64_t index : {27, 28, 29, 30, 31, 32}) stream.expect(index);
  stream.offer(frame_with_index(27));
  stream.offer(frame_with_index(28));
  EXPECT_EQ(stream.dropped(), 0u);  // 29 was replaced in the encoder's queue by 30: not yet seen
  stream.offer(frame_with_index(30));
  EXPECT_EQ(stream.dropped(), 1u);  // 29: skipped before 30
  stream.offer(frame_with_index(32));
  stream.offer(frame_with_index(31));  // an encoder thread finished it after 32: never sent
  EXPECT_EQ(stream.dropped(), 2u);
  EXPECT_EQ(metrics.frames_dropped.load(), 2u);
}

TEST(TextTest, ClientTextIsEscapedAndCut) {
  EXPECT_EQ(service::printable("ok"), "'ok'");
  EXPECT_EQ(service::printable(std::string("a\nb\0c'", 6)), "'a\\x0ab\\x00c\\x27'");
  EXPECT_EQ(service::printable(std::string(100, 'x'), 4), "'xxxx...'");
}

}  // namespace
}  // namespace ddgi::test
