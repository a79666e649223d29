// Downloading from a session as a client does: a whole DumpAtlas or ExportScene stream with
// its chunks checked, and the field's dumps (irradiance and distance atlases, or SH coefficients;
// probe states) plus the two query parameters put together as a ProbeField (probe_field.h),
// taken again until every dump comes from one field update.
// ddgi-client (atlas, probes) and the service tests use it.
#pragma once

#include <grpcpp/grpcpp.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.grpc.pb.h"
#include "rpc/probe_field.h"

namespace ddgi {

// Makes the context of each call (token, deadline).
using ContextFactory = std::function<std::unique_ptr<grpc::ClientContext>()>;

// A whole DumpAtlas stream: its metadata and bytes; DATA_LOSS when chunks come out of order,
// beyond the announced size, or short of it.
grpc::Status fetch_atlas(v1::RenderService::Stub& stub, const ContextFactory& context,
                         const v1::DumpAtlasRequest& request, v1::AtlasMetadata* metadata,
                         std::string* bytes);

// A whole ExportScene stream (the session's scene as .glb), checked as fetch_atlas checks;
// `progress` (optional) hears the bytes received so far after each chunk.
grpc::Status fetch_scene(v1::RenderService::Stub& stub, const ContextFactory& context,
                         const v1::ExportSceneRequest& request, v1::SceneMetadata* metadata,
                         std::string* bytes, const std::function<void(uint64_t)>& progress = {});

// The float32 texels of a RAW_F32 atlas (little-endian, as the service sends them).
std::vector<float> raw_floats(const std::string& bytes);

struct DownloadedField {
  ProbeField field;
  uint64_t field_updates = 0;  // the update every dump comes from
};

// The session's irradiance field; UNAVAILABLE when it changed during each of a few attempts
// (a session streaming frames updates it meanwhile).
Result<DownloadedField> download_probe_field(v1::RenderService::Stub& stub,
                                             const ContextFactory& context,
                                             const std::string& session_id);

}  // namespace ddgi
