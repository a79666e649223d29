// Downloads a whole DumpAtlas stream, keeping every chunk's offset and size so that tests can
// check the chunking as well as the bytes.
#pragma once

#include <grpcpp/grpcpp.h>

#include <string>
#include <vector>

#include "ddgi/v1/render_service.grpc.pb.h"
#include "rpc/probe_download.h"  // raw_floats

namespace ddgi::test {

struct AtlasDownload {
  grpc::Status status;
  v1::AtlasMetadata metadata;
  std::string bytes;                  // the data chunks, concatenated in arrival order
  std::vector<uint64_t> offsets;      // each data chunk's offset field
  std::vector<uint64_t> sizes;        // each data chunk's data size
  std::vector<size_t> message_sizes;  // each message's encoded size, metadata message first
};

// `volume`: DumpAtlasRequest.volume (of a field of cascades).
AtlasDownload download_atlas(v1::RenderService::Stub& stub, const std::string& session_id,
                             v1::AtlasKind kind, v1::AtlasFormat format,
                             const std::string& token = "", uint32_t volume = 0);

}  // namespace ddgi::test
