#include "tests/service/atlas_download.h"

#include <chrono>

namespace ddgi::test {

AtlasDownload download_atlas(v1::RenderService::Stub& stub, const std::string& session_id,
                             v1::AtlasKind kind, v1::AtlasFormat format, const std::string& token,
                             uint32_t volume) {
  v1::DumpAtlasRequest request;
  request.set_session_id(session_id);
  request.set_kind(kind);
  request.set_format(format);
  request.set_volume(volume);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
  auto reader = stub.DumpAtlas(&context, request);
  AtlasDownload out;
  v1::AtlasChunk chunk;
  bool first = true;
  while (reader->Read(&chunk)) {
    out.message_sizes.push_back(chunk.ByteSizeLong());
    if (first) {
      out.metadata = chunk.metadata();
      first = false;
      continue;
    }
    out.offsets.push_back(chunk.offset());
    out.sizes.push_back(chunk.data().size());
    out.bytes += chunk.data();
  }
  out.status = reader->Finish();
  return out;
}

}  // namespace ddgi::test
