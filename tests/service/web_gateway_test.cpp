// The web front (server/service/web_gateway.h) from a WebSocket client's side: requests reach
// the RenderService with its own validation and auth, unreadable messages are refused with a
// reply naming why (and the connection keeps working), frames stream with the camera commands
// they show, a stream ends with a status the browser sees, the connection limit holds, and the
// page's files are served (and nothing outside them).
#include <civetweb.h>

#include "encode/jpeg.h"
#include "rpc/web_link.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

constexpr const char* kToken = "web-test-token-0123456789";

class WebGatewayTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override {
    options.web.port = 0;
    options.web.address = "127.0.0.1";
    options.web.root = DDGI_TEST_WEB_ROOT;
    options.web.max_connections = 3;
    options.auth_token = kToken;
    token_ = kToken;
  }
  int web_port() { return server().web_port(); }

  std::unique_ptr<WebLink> connect() {
    Result<std::unique_ptr<WebLink>> link = WebLink::connect("127.0.0.1", web_port());
    EXPECT_TRUE(link.ok()) << link.error().message;
    return link.ok() ? std::move(*link) : nullptr;
  }
  // A connected client that said hello with the right token.
  std::unique_ptr<WebLink> hello_client() {
    auto client = connect();
    if (!client) return nullptr;
    v1::WebRequest hello;
    hello.mutable_hello()->set_token(kToken);
    const v1::WebReply reply = client->call(hello);
    EXPECT_TRUE(reply.has_server_info()) << reply.DebugString();
    return client;
  }
};

// The refusal (id 0) of the last unreadable message.
v1::WebError refusal(WebLink& client) {
  v1::WebReply reply;
  EXPECT_TRUE(client.wait_reply(0, &reply));
  return reply.error();
}

TEST_F(WebGatewayTest, CallsGoThroughTheApiWithItsAuthAndValidation) {
  auto link = connect();
  ASSERT_TRUE(link);
  WebLink& client = *link;
  v1::WebRequest hello;
  hello.mutable_hello()->set_token("not-the-token");
  v1::WebReply reply = client.call(hello);
  EXPECT_EQ(reply.error().code(), "UNAUTHENTICATED") << reply.DebugString();
  EXPECT_EQ(reply.error().message(), "invalid bearer token");
  v1::WebRequest list;
  list.mutable_list_sessions();
  EXPECT_EQ(client.call(list).error().code(), "UNAUTHENTICATED") << "the refused token is used";

  hello.mutable_hello()->set_token(kToken);
  reply = client.call(hello);
  ASSERT_TRUE(reply.has_server_info()) << reply.DebugString();
  EXPECT_TRUE(reply.server_info().auth_required());
  EXPECT_EQ(reply.id(), 3u) << "replies carry their request's id";

  // The service's own validation, not the gateway's: an unknown scene, a non-finite camera.
  v1::WebRequest create;
  create.mutable_create_session()->mutable_scene()->set_name("no_such_scene");
  EXPECT_EQ(client.call(create).error().code(), "NOT_FOUND");
  client.send_text(R"({"id": "9", "setCamera": {"sessionId": "s0000000000000000",
      "viewId": "v1", "camera": {"position": {"x": "NaN"}}}})");
  v1::WebReply camera;
  ASSERT_TRUE(client.wait_reply(9, &camera));
  EXPECT_EQ(camera.error().code(), "INVALID_ARGUMENT") << camera.DebugString();
  EXPECT_NE(camera.error().message().find("finite"), std::string::npos) << camera.DebugString();
}

TEST_F(WebGatewayTest, UnreadableMessagesAreRefusedAndTheConnectionKeepsWorking) {
  auto client = hello_client();
  const uint64_t refused_before = server().metrics().web_messages_refused.load();
  client->send_text("not json");
  v1::WebError error = refusal(*client);
  EXPECT_EQ(error.code(), "INVALID_ARGUMENT");
  EXPECT_NE(error.message().find("not a WebRequest in JSON"), std::string::npos) << error.message();
  client->send_text(R"({"id": "5", "hello": {}, "volume": 11})");
  error = refusal(*client);
  EXPECT_NE(error.message().find("volume"), std::string::npos) << error.message();
  client->send_text(R"({"id": "6"})");
  EXPECT_NE(refusal(*client).message().find("names no call"), std::string::npos);
  client->send_binary(std::string(64, '\x01'));
  EXPECT_NE(refusal(*client).message().find("only whole text messages"), std::string::npos);
  client->send_text(std::string(service::WebGateway::kMaxTextBytes + 1, ' '));
  EXPECT_NE(refusal(*client).message().find("over the limit"), std::string::npos);
  EXPECT_EQ(server().metrics().web_messages_refused.load() - refused_before, 5u);

  v1::WebRequest list;
  list.mutable_list_sessions();
  EXPECT_TRUE(client->call(list).has_sessions()) << "the connection still serves calls";
}

TEST_F(WebGatewayTest, FramesStreamAndShowTheCameraCommand) {
  auto client = hello_client();
  v1::WebRequest create;
  *create.mutable_create_session() = small_session_request("cornell_box", 2);
  const v1::WebReply session = client->call(create);
  ASSERT_TRUE(session.has_session()) << session.DebugString();
  const std::string session_id = session.session().session_id();

  v1::WebRequest stream;
  stream.mutable_stream_frames()->set_session_id(session_id);
  stream.mutable_stream_frames()->mutable_settings()->set_width(64);
  stream.mutable_stream_frames()->mutable_settings()->set_height(48);
  ASSERT_TRUE(client->call(stream).has_stream_started());
  const uint64_t stream_id = 3;  // hello 1, create 2, stream 3
  ASSERT_TRUE(client->wait_frames(2));
  const v1::Frame first = client->last_frame();
  EXPECT_EQ(first.width(), 64u);
  EXPECT_EQ(first.session_id(), session_id);
  EXPECT_FALSE(first.view_id().empty());
  Result<encode::ImageRgba8> image = encode::decode_jpeg(
      std::span(reinterpret_cast<const uint8_t*>(first.jpeg().data()), first.jpeg().size()));
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, 64u);
  double sum = 0.0;
  for (size_t i = 0; i < image->pixels.size(); ++i) sum += i % 4 == 3 ? 0.0 : image->pixels[i];
  EXPECT_GT(sum / (0.75 * double(image->pixels.size())), 10.0) << "the frame is black";

  v1::WebRequest camera;
  camera.mutable_set_camera()->set_session_id(session_id);
  camera.mutable_set_camera()->set_view_id(first.view_id());
  *camera.mutable_set_camera()->mutable_camera() = look_at(0.5f, 1.5f, 2.5f, 0.0f, 1.0f, 0.0f);
  const v1::WebReply view = client->call(camera);
  ASSERT_TRUE(view.has_view()) << view.DebugString();
  const uint64_t seq = view.view().command_seq();
  EXPECT_GT(seq, first.last_command_seq());
  ASSERT_TRUE(client->wait_command(seq)) << "no frame showed the camera command";
  const v1::Frame moved = client->last_frame();
  EXPECT_NEAR(moved.camera().position().x(), 0.5f, 1e-5f);
  EXPECT_NEAR(moved.camera().position().z(), 2.5f, 1e-5f);

  // The session closing ends the stream with OK, under the stream request's id.
  grpc::ClientContext context;
  context.AddMetadata("authorization", std::string("Bearer ") + kToken);
  v1::CloseSessionRequest close;
  close.set_session_id(session_id);
  v1::CloseSessionReply closed;
  ASSERT_TRUE(stub_->CloseSession(&context, close, &closed).ok());
  v1::WebReply ended;
  ASSERT_TRUE(client->wait_reply(stream_id, &ended));
  EXPECT_EQ(ended.stream_ended().code(), "OK") << ended.DebugString();
}

TEST_F(WebGatewayTest, AStreamOfAnUnknownSessionEndsWithItsError) {
  auto client = hello_client();
  v1::WebRequest stream;
  stream.mutable_stream_frames()->set_session_id("s0000000000000000");
  const v1::WebReply started = client->call(stream);
  ASSERT_TRUE(started.has_stream_started());
  v1::WebReply ended;
  ASSERT_TRUE(client->wait_reply(started.id(), &ended));
  EXPECT_EQ(ended.stream_ended().code(), "NOT_FOUND") << ended.DebugString();
  EXPECT_EQ(client->frames(), 0u);
}

TEST_F(WebGatewayTest, ConnectionsBeyondTheLimitAreRefusedAndFreedOnClose) {
  std::vector<std::unique_ptr<WebLink>> clients;
  for (int i = 0; i < 3; ++i) clients.push_back(hello_client());
  Result<std::unique_ptr<WebLink>> over = WebLink::connect("127.0.0.1", web_port());
  EXPECT_FALSE(over.ok() && !(*over)->closed()) << "a fourth WebSocket was accepted";
  EXPECT_EQ(server().metrics().web_connections.load(), 3);
  clients.pop_back();
  for (int i = 0; i < 100 && server().metrics().web_connections.load() > 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(server().metrics().web_connections.load(), 2) << "a closed connection was not freed";
  EXPECT_TRUE(hello_client()) << "no connection after one was freed";
}

// The page's files, and nothing else: no listing, no path out of the folder.
TEST_F(WebGatewayTest, ServesThePageAndNothingOutsideIt) {
  auto get = [&](const std::string& path, std::string* body) {
    char error[256] = {};
    mg_connection* connection = mg_download("127.0.0.1", web_port(), 0, error, sizeof(error),
                                            "GET %s HTTP/1.0\r\n\r\n", path.c_str());
    if (connection == nullptr) return -1;
    const int status = mg_get_response_info(connection)->status_code;
    char buffer[4096];
    int n = 0;
    while ((n = mg_read(connection, buffer, sizeof(buffer))) > 0) body->append(buffer, n);
    mg_close_connection(connection);
    return status;
  };
  std::string page, script, listing, escape;
  EXPECT_EQ(get("/", &page), 200);
  EXPECT_NE(page.find("<canvas id=\"frame\""), std::string::npos);
  EXPECT_EQ(get("/app.js", &script), 200);
  EXPECT_NE(script.find("DdgiSocket"), std::string::npos);
  EXPECT_EQ(get("/../CMakeLists.txt", &escape), 404);
  EXPECT_EQ(escape.find("cmake_minimum_required"), std::string::npos);
  EXPECT_NE(get("/%2e%2e/CMakeLists.txt", &escape), 200);
  EXPECT_EQ(escape.find("cmake_minimum_required"), std::string::npos);
}

}  // namespace
}  // namespace ddgi::test
