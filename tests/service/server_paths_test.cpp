// Errors of library scenes that cannot be loaded (a missing buffer, a sidecar naming a missing
// scene or environment map, a scene outside the library, broken JSON) reach the client without
// any absolute path of the server: paths inside the library are relative to it, others keep
// only their file name. The log keeps the whole message for the operator.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <string>

#include "service/scene_library.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

namespace fs = std::filesystem;

// An absolute path as it would appear in a message: '/' at the start or after a separator,
// followed by a path character.
bool has_absolute_path(const std::string& text) {
  static const std::regex kAbsolute(R"((^|[\s'"`(=,\[])/[A-Za-z0-9._~-])");
  return std::regex_search(text, kAbsolute);
}

void write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

const char* const kBufferMissing = R"({"asset": {"version": "2.0"},
  "buffers": [{"uri": "missing.bin", "byteLength": 36}]})";

class ServerPathsTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override {
    base_ = fs::path(::testing::TempDir()) / ("ddgi_paths_" + std::to_string(::getpid()));
    fs::remove_all(base_);
    const fs::path library = base_ / "library";
    write(library / "buffer_missing.gltf", kBufferMissing);
    write(library / "scene_missing.ddgi.json", R"({"scene": "gone.gltf"})");
    write(library / "environment_missing.ddgi.json",
          R"({"scene": "sub/room.gltf", "environment": {"image": "sky_missing.exr"}})");
    fs::create_directories(library / "sub");
    fs::copy_file(fs::path(DDGI_TEST_SCENE_ROOT) / "cornell_box.gltf",
                  library / "sub" / "room.gltf");
    write(library / "outside.ddgi.json", R"({"scene": "../elsewhere/far.gltf"})");
    write(base_ / "elsewhere" / "far.gltf", kBufferMissing);
    write(library / "broken_json.ddgi.json", R"({"scene": )");
    write(library / "escape.gltf", R"({"asset": {"version": "2.0"},
      "buffers": [{"uri": "../elsewhere/far.gltf", "byteLength": 4}]})");
    options.scene_root = library.string();
  }
  void TearDown() override {
    ServiceTest::TearDown();
    fs::remove_all(base_);
  }

  grpc::Status load(const std::string& name) {
    v1::CreateSessionRequest request = small_session_request(name, 0);
    v1::SessionInfo info;
    auto ctx = context();
    return stub_->CreateSession(ctx.get(), request, &info);
  }

  fs::path base_;
};

TEST_F(ServerPathsTest, LibrarySceneErrorsCarryNoServerPath) {
  struct Case {
    const char* scene;
    const char* names;  // what the message still says, relative to the library
  };
  const Case cases[] = {
      {"buffer_missing",
       "<library>/buffer_missing.gltf: uri 'missing.bin': file not found in <library>"},
      {"scene_missing", "<library>/gone.gltf: no such file"},
      {"environment_missing", "<library>/sky_missing.exr: no such file"},
      {"outside",
       "<library>/../elsewhere/far.gltf: uri 'missing.bin': file not found in "
       ".../elsewhere"},
      {"broken_json", "<library>/broken_json.ddgi.json: invalid JSON"},
      {"escape", "uri '../elsewhere/far.gltf' resolves outside the scene folder <library>"},
  };
  for (const Case& c : cases) {
    const grpc::Status status = load(c.scene);
    EXPECT_FALSE(status.ok()) << c.scene;
    const std::string& message = status.error_message();
    std::cout << c.scene << ": " << grpc::StatusCode(status.error_code()) << " " << message << "\n";
    EXPECT_FALSE(has_absolute_path(message)) << c.scene << ": " << message;
    EXPECT_EQ(message.find(base_.string()), std::string::npos) << c.scene << ": " << message;
    EXPECT_NE(message.find(c.names), std::string::npos) << c.scene << ": " << message;
  }
  // The server still serves.
  v1::ServerInfo info;
  auto ctx = context();
  EXPECT_TRUE(stub_->GetServerInfo(ctx.get(), {}, &info).ok());
}

TEST(RedactPathsTest, RootsBecomeRelativeOtherPathsKeepTheirFileName) {
  const std::vector<std::string> roots = {"/srv/ddgi/scenes/real", "/srv/scenes"};
  EXPECT_EQ(service::redact_paths("/srv/scenes/a.gltf: uri 'b.bin': file not found in "
                                  "/srv/scenes",
                                  roots, "<library>"),
            "<library>/a.gltf: uri 'b.bin': file not found in <library>");
  EXPECT_EQ(service::redact_paths("/srv/ddgi/scenes/real/sub/x.gltf: bad", roots, "L"),
            "L/sub/x.gltf: bad");
  EXPECT_EQ(service::redact_paths("scene: names /home/op/secret/x.gltf, but (/etc/y)", roots, "L"),
            "scene: names .../x.gltf, but (.../y)");
  EXPECT_EQ(service::redact_paths("uri '/etc/passwd' is an absolute path", roots, "L"),
            "uri '.../passwd' is an absolute path");
  // Not paths: slashes inside words and numbers, a lone slash.
  for (const char* kept : {"W/m2 at 1/2", "a / b", "counts=4,4,4 and x/y", ""}) {
    EXPECT_EQ(service::redact_paths(kept, roots, "L"), kept);
  }
  EXPECT_EQ(service::redact_paths("/srv/scenesX/a.gltf", roots, "L"), ".../a.gltf");
}

}  // namespace
}  // namespace ddgi::test
