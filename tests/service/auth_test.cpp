// Bearer-token auth: missing or wrong tokens are UNAUTHENTICATED on every RenderService call
// (unary and streaming), the scheme in any case; the health service and (by decision)
// reflection answer without one; tokens never reach the log.
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "grpc/health/v1/health.grpc.pb.h"
#include "tests/service/reflection_probe.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

constexpr const char* kToken = "s3cret-t0ken-for-tests";

class AuthTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override { options.auth_token = kToken; }

  grpc::Status info_with(const std::string& authorization) {
    grpc::ClientContext ctx;
    if (!authorization.empty()) ctx.AddMetadata("authorization", authorization);
    v1::ServerInfo info;
    return stub_->GetServerInfo(&ctx, {}, &info);
  }
};

TEST_F(AuthTest, MissingOrWrongTokenIsUnauthenticated) {
  testing::internal::CaptureStderr();
  grpc::Status status = info_with("");
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(status.error_message().find("missing 'authorization: Bearer <token>'"),
            std::string::npos)
      << status.error_message();
  status = info_with("Bearer wrong-token-value");
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(status.error_message(), "invalid bearer token");
  status = info_with(kToken);  // no "Bearer " scheme
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  status = info_with(std::string("Bearer ") + kToken + "x");
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);

  // Streaming calls are guarded the same way.
  v1::StreamFramesRequest request;
  request.set_session_id("s0000000000000000");
  StreamWatcher stream(*stub_, request, "wrong-token-value");
  status = stream.wait_end();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  v1::DumpAtlasRequest dump;
  grpc::ClientContext ctx;
  auto reader = stub_->DumpAtlas(&ctx, dump);
  v1::AtlasChunk chunk;
  EXPECT_FALSE(reader->Read(&chunk));
  EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);

  const std::string log = testing::internal::GetCapturedStderr();
  EXPECT_EQ(log.find(kToken), std::string::npos) << "the token was logged";
  EXPECT_EQ(log.find("wrong-token-value"), std::string::npos) << "a presented token was logged";
}

TEST_F(AuthTest, RightTokenWorks) {
  EXPECT_TRUE(info_with(std::string("Bearer ") + kToken).ok());
  token_ = kToken;
  const std::string session = create_session();
  v1::Frame frame;
  ASSERT_TRUE(render(session, 16, 12, &frame).ok());
  v1::StreamFramesRequest request;
  request.set_session_id(session);
  request.mutable_settings()->set_width(16);
  request.mutable_settings()->set_height(12);
  StreamWatcher stream(*stub_, request, kToken);
  EXPECT_TRUE(stream.wait_for(2, 30.0));
}

// HTTP authentication schemes are case-insensitive (RFC 9110 section 11.1), and one or more
// spaces may follow the scheme; the token itself is compared exactly.
TEST_F(AuthTest, SchemeIsCaseInsensitive) {
  for (const char* scheme : {"Bearer ", "bearer ", "BEARER ", "bEaReR ", "Bearer   "}) {
    const grpc::Status status = info_with(scheme + std::string(kToken));
    EXPECT_TRUE(status.ok()) << "'" << scheme << "': " << status.error_message();
  }
  for (const std::string& refused :
       {std::string("Bearer") + kToken, std::string("Basic ") + kToken,
        std::string("bearer S3CRET-T0KEN-FOR-TESTS"), std::string("bearer x") + kToken,
        std::string("bearer "), std::string("bearer")}) {
    const grpc::Status status = info_with(refused);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED) << "'" << refused << "'";
  }
}

TEST_F(AuthTest, HealthAnswersWithoutToken) {
  auto health = grpc::health::v1::Health::NewStub(channel_);
  grpc::ClientContext ctx;
  grpc::health::v1::HealthCheckRequest request;
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = health->Check(&ctx, request, &response);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(response.status(), grpc::health::v1::HealthCheckResponse::SERVING);
}

// Decided (docs/service.md, "Auth and TLS"): reflection stays open like health. It describes
// only the published API (render_service.proto, health, reflection), nothing of the server's
// state; gRPC offers no hook in front of its reflection service, and --no-reflection closes it.
TEST_F(AuthTest, ReflectionAnswersWithoutTokenByDecision) {
  const ReflectionAnswer answer = list_services(channel_);
  ASSERT_TRUE(answer.status.ok()) << answer.status.error_message();
  EXPECT_NE(answer.text.find("ddgi.v1.RenderService"), std::string::npos);
  EXPECT_EQ(answer.text.find(kToken), std::string::npos);
}

// TLS: the server presents a certificate made for this test; a client trusting it connects, a
// plaintext client does not.
class TlsTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override {
    dir_ = testing::TempDir() + "/ddgi_tls_" + std::to_string(::getpid());
    const std::string command =
        "mkdir -p " + dir_ +
        " && openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj "
        "/CN=localhost -addext subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout " +
        dir_ + "/key.pem -out " + dir_ + "/cert.pem 2>/dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << "openssl could not make a certificate";
    options.tls_cert_file = dir_ + "/cert.pem";
    options.tls_key_file = dir_ + "/key.pem";
  }
  std::string dir_;
};

TEST_F(TlsTest, TrustedClientConnectsPlaintextDoesNot) {
  std::ifstream cert(dir_ + "/cert.pem");
  std::stringstream pem;
  pem << cert.rdbuf();
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs = pem.str();
  grpc::ChannelArguments args;
  args.SetSslTargetNameOverride("localhost");
  auto secure = grpc::CreateCustomChannel(address(), grpc::SslCredentials(ssl), args);
  auto stub = v1::RenderService::NewStub(secure);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
  v1::ServerInfo info;
  const grpc::Status status = stub->GetServerInfo(&ctx, {}, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();

  auto plain_ctx = context(5.0);
  const grpc::Status plain = stub_->GetServerInfo(plain_ctx.get(), {}, &info);
  EXPECT_EQ(plain.error_code(), grpc::StatusCode::UNAVAILABLE);
}

}  // namespace
}  // namespace ddgi::test
