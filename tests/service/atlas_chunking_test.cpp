// Atlas dumps larger than the message limit arrive in chunks: on a server with the smallest
// allowed limit (64 KiB) a 6x6x6-probe irradiance atlas takes several chunks, each message fits
// the limit, offsets are contiguous and the bytes reassemble to exactly what a server with a
// large limit sends in one chunk. The EXR form decodes (through the project's EXR reader) to
// the raw floats, and the metadata (in the first message and the EXR header) describes the
// field the session runs.
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfStringAttribute.h>

#include <cstdio>
#include <fstream>

#include "encode/exr.h"
#include "gi/field_params.h"
#include "tests/service/atlas_download.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

constexpr uint64_t kSmallMessageBytes = 64 << 10;  // the least --max-message-bytes allows
constexpr uint32_t kWarmup = 2;

class AtlasChunkingTest : public ServiceTest {
 protected:
  void configure(service::ServerOptions& options) override {
    options.limits.max_message_bytes = kSmallMessageBytes;
  }
  // The same session on any server: cornell_box, 6x6x6 probes, 16 + 8 rays, 2 warm-up updates
  // and no frames, so its field is a function of these values alone (seeded ray rotations).
  static std::string create_grid_session(v1::RenderService::Stub& stub,
                                         const v1::CreateSessionRequest& request) {
    v1::SessionInfo info;
    grpc::ClientContext ctx;
    ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(120));
    const grpc::Status status = stub.CreateSession(&ctx, request, &info);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return info.session_id();
  }
  v1::CreateSessionRequest grid_request() const {
    v1::CreateSessionRequest request = small_session_request("cornell_box", kWarmup);
    EXPECT_EQ(request.field_params(0).name(), "counts");
    request.mutable_field_params(0)->set_value("6,6,6");
    return request;
  }
  static void expect_contiguous(const AtlasDownload& dump, size_t min_chunks) {
    ASSERT_TRUE(dump.status.ok()) << dump.status.error_message();
    EXPECT_GE(dump.offsets.size(), min_chunks);
    uint64_t expected = 0;
    for (size_t i = 0; i < dump.offsets.size(); ++i) {
      EXPECT_EQ(dump.offsets[i], expected) << "chunk " << i;
      EXPECT_GT(dump.sizes[i], 0u) << "chunk " << i;
      expected += dump.sizes[i];
    }
    EXPECT_EQ(expected, dump.metadata.total_bytes());
    EXPECT_EQ(dump.bytes.size(), dump.metadata.total_bytes());
  }
};

TEST_F(AtlasChunkingTest, ChunksReassembleToTheSingleChunkDump) {
  const std::string session = create_grid_session(*stub_, grid_request());
  v1::GetFieldParamsRequest get;
  get.set_session_id(session);
  v1::FieldParams reply;
  auto ctx = context();
  ASSERT_TRUE(stub_->GetFieldParams(ctx.get(), get, &reply).ok());
  IrradianceFieldParams params;
  std::vector<std::string> assignments;
  for (const auto& p : reply.params()) assignments.push_back(p.name() + "=" + p.value());
  ASSERT_TRUE(field_param_table().apply(params, assignments).ok());
  ASSERT_EQ(params.counts, glm::ivec3(6));

  const AtlasDownload raw =
      download_atlas(*stub_, session, v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_FORMAT_RAW_F32);
  expect_contiguous(raw, 3);
  for (size_t size : raw.message_sizes) EXPECT_LE(size, kSmallMessageBytes);
  std::printf("irradiance atlas %ux%u: %llu bytes in %zu chunks of at most %llu bytes\n",
              raw.metadata.width(), raw.metadata.height(),
              static_cast<unsigned long long>(raw.metadata.total_bytes()), raw.offsets.size(),
              static_cast<unsigned long long>(raw.sizes.empty() ? 0 : raw.sizes[0]));

  // The metadata describes the field in effect.
  const v1::AtlasMetadata& m = raw.metadata;
  EXPECT_EQ(m.kind(), v1::ATLAS_KIND_IRRADIANCE);
  EXPECT_EQ(m.format(), v1::ATLAS_FORMAT_RAW_F32);
  EXPECT_EQ(m.probe_counts_x(), 6);
  EXPECT_EQ(m.probe_counts_y(), 6);
  EXPECT_EQ(m.probe_counts_z(), 6);
  EXPECT_EQ(m.texels_per_probe(), params.irradiance_texels);
  EXPECT_FLOAT_EQ(m.encoding_gamma(), params.irradiance_gamma);
  EXPECT_EQ(m.border_texels(), 1u);
  EXPECT_EQ(m.field_updates(), kWarmup);
  EXPECT_EQ(m.field_updates(), reply.updates());
  const uint32_t tile = params.irradiance_texels + 2 * m.border_texels();
  ASSERT_GT(m.tiles_per_row(), 0u);
  EXPECT_EQ(m.width(), m.tiles_per_row() * tile);
  EXPECT_EQ(m.height(), (216 + m.tiles_per_row() - 1) / m.tiles_per_row() * tile);
  EXPECT_EQ(m.total_bytes(), uint64_t(m.width()) * m.height() * 4 * sizeof(float));
  ASSERT_EQ(m.channels_size(), 4);
  EXPECT_EQ(m.channels(0), "R");
  EXPECT_EQ(m.channels(3), "A");
  // Text round trip of the parameters: 1e-4 relative.
  for (int axis = 0; axis < 3; ++axis) {
    const float origin[] = {m.grid_origin().x(), m.grid_origin().y(), m.grid_origin().z()};
    const float spacing[] = {m.probe_spacing().x(), m.probe_spacing().y(), m.probe_spacing().z()};
    EXPECT_NEAR(origin[axis], params.origin[axis], 1e-4f * (1.0f + std::abs(params.origin[axis])));
    EXPECT_NEAR(spacing[axis], params.spacing[axis], 1e-4f * params.spacing[axis]);
  }

  // A server with a large message limit sends the same session's atlas in one chunk.
  {
    service::ServerOptions options = test_server_options();
    options.limits.max_message_bytes = 16ull << 20;
    options.metrics_port = -1;
    auto large = service::Server::start(service_context(), options);
    ASSERT_TRUE(large.ok()) << large.error().message;
    grpc::ChannelArguments args;
    args.SetMaxReceiveMessageSize(64 << 20);
    auto channel = grpc::CreateCustomChannel("127.0.0.1:" + std::to_string((*large)->port()),
                                             grpc::InsecureChannelCredentials(), args);
    auto stub = v1::RenderService::NewStub(channel);
    const std::string other = create_grid_session(*stub, grid_request());
    const AtlasDownload single =
        download_atlas(*stub, other, v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_FORMAT_RAW_F32);
    expect_contiguous(single, 1);
    EXPECT_EQ(single.offsets.size(), 1u);
    EXPECT_EQ(single.metadata.total_bytes(), raw.metadata.total_bytes());
    const std::vector<float> a = raw_floats(raw.bytes), b = raw_floats(single.bytes);
    ASSERT_EQ(a.size(), b.size());
    size_t differing = 0;
    for (size_t i = 0; i < a.size(); ++i) differing += a[i] != b[i] ? 1 : 0;
    EXPECT_EQ(differing, 0u) << "of " << a.size() << " floats";
    EXPECT_TRUE((*large)->shutdown());
  }

  // The EXR form, chunked the same way, decodes to the raw floats (R, G, B: what the project's
  // reader returns) bit for bit, and its header repeats the metadata.
  const AtlasDownload exr =
      download_atlas(*stub_, session, v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_FORMAT_EXR);
  expect_contiguous(exr, 2);
  for (size_t size : exr.message_sizes) EXPECT_LE(size, kSmallMessageBytes);
  const std::string path = testing::TempDir() + "/atlas_chunking_" +
                           std::to_string(reinterpret_cast<uintptr_t>(this)) + ".exr";
  {
    std::ofstream file(path, std::ios::binary);
    file.write(exr.bytes.data(), std::streamsize(exr.bytes.size()));
    ASSERT_TRUE(file.good());
  }
  auto decoded = encode::read_exr(path);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message;
  ASSERT_EQ(decoded->width, m.width());
  ASSERT_EQ(decoded->height, m.height());
  const std::vector<float> texels = raw_floats(raw.bytes);
  size_t differing = 0;
  for (size_t t = 0; t < size_t(m.width()) * m.height(); ++t) {
    for (size_t c = 0; c < 3; ++c) differing += decoded->rgb[t * 3 + c] != texels[t * 4 + c];
  }
  EXPECT_EQ(differing, 0u) << "EXR texels differ from the raw dump";
  Imf::InputFile file(path.c_str());
  auto attribute = [&](const char* name) {
    const auto* value = file.header().findTypedAttribute<Imf::StringAttribute>(name);
    return value ? value->value() : std::string("<absent>");
  };
  EXPECT_EQ(attribute("ddgi.probe_counts"), "6 6 6");
  EXPECT_EQ(attribute("ddgi.texels_per_probe"), std::to_string(params.irradiance_texels));
  EXPECT_EQ(attribute("ddgi.field_updates"), std::to_string(kWarmup));
  EXPECT_EQ(std::stof(attribute("ddgi.encoding_gamma")), params.irradiance_gamma);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace ddgi::test
