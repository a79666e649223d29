#include "rpc/probe_download.h"

#include <algorithm>
#include <cstring>

namespace ddgi {
std::vector<float> raw_floats(const std::string& bytes) {
  std::vector<float> values(bytes.size() / sizeof(float));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(float));  // little-endian
  return values;
}

namespace {

// The field from its three RAW_F32 atlases (irradiance, distance, probe states).
ProbeField field_from_atlases(const v1::AtlasMetadata meta[3], const std::string bytes[3]) {
  ProbeField f;
  const v1::AtlasMetadata& m = meta[0];
  f.counts[0] = m.probe_counts_x();
  f.counts[1] = m.probe_counts_y();
  f.counts[2] = m.probe_counts_z();
  f.origin = {m.grid_origin().x(), m.grid_origin().y(), m.grid_origin().z()};
  f.spacing = {m.probe_spacing().x(), m.probe_spacing().y(), m.probe_spacing().z()};
  f.irradiance_texels = m.texels_per_probe();
  f.border_texels = m.border_texels();
  f.tiles_per_row = m.tiles_per_row();
  f.irradiance_gamma = m.encoding_gamma();
  f.irradiance_width = m.width();
  f.irradiance_height = m.height();
  f.irradiance = raw_floats(bytes[0]);
  f.distance_texels = meta[1].texels_per_probe();
  f.distance_width = meta[1].width();
  f.distance_height = meta[1].height();
  f.distance = raw_floats(bytes[1]);
  f.probe_states = raw_floats(bytes[2]);
  return f;
}

}  // namespace

grpc::Status fetch_atlas(v1::RenderService::Stub& stub, const ContextFactory& context,
                         const v1::DumpAtlasRequest& request, v1::AtlasMetadata* metadata,
                         std::string* bytes) {
  const std::unique_ptr<grpc::ClientContext> call = context();
  auto reader = stub.DumpAtlas(call.get(), request);
  v1::AtlasChunk chunk;
  bool have_metadata = false;
  bytes->clear();
  while (reader->Read(&chunk)) {
    if (chunk.has_metadata()) {
      *metadata = chunk.metadata();
      have_metadata = true;
      bytes->reserve(size_t(std::min<uint64_t>(metadata->total_bytes(), 1ull << 32)));
      continue;
    }
    if (!have_metadata || chunk.offset() != bytes->size() ||
        bytes->size() + chunk.data().size() > metadata->total_bytes()) {
      call->TryCancel();
      (void)reader->Finish();
      return grpc::Status(grpc::StatusCode::DATA_LOSS,
                          "atlas chunks out of order or beyond the announced size");
    }
    *bytes += chunk.data();
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return status;
  if (!have_metadata || bytes->size() != metadata->total_bytes()) {
    return grpc::Status(grpc::StatusCode::DATA_LOSS,
                        "atlas ended after " + std::to_string(bytes->size()) + " of " +
                            std::to_string(metadata->total_bytes()) + " bytes");
  }
  return grpc::Status::OK;
}

Result<DownloadedField> download_probe_field(v1::RenderService::Stub& stub,
                                             const ContextFactory& context,
                                             const std::string& session_id) {
  constexpr int kAttempts = 5;
  const v1::AtlasKind kinds[3] = {v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_KIND_DISTANCE,
                                  v1::ATLAS_KIND_PROBE_STATES};
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    v1::AtlasMetadata meta[3];
    std::string bytes[3];
    for (int i = 0; i < 3; ++i) {
      v1::DumpAtlasRequest request;
      request.set_session_id(session_id);
      request.set_kind(kinds[i]);
      request.set_format(v1::ATLAS_FORMAT_RAW_F32);
      if (const grpc::Status status = fetch_atlas(stub, context, request, &meta[i], &bytes[i]);
          !status.ok()) {
        return unavailable("DumpAtlas: " + status.error_message());
      }
    }
    if (meta[0].field_updates() != meta[1].field_updates() ||
        meta[1].field_updates() != meta[2].field_updates()) {
      continue;  // an update came between two downloads
    }
    DownloadedField out{field_from_atlases(meta, bytes), meta[0].field_updates()};
    v1::GetFieldParamsRequest request;
    request.set_session_id(session_id);
    v1::FieldParams params;
    const std::unique_ptr<grpc::ClientContext> call = context();
    if (const grpc::Status status = stub.GetFieldParams(call.get(), request, &params);
        !status.ok()) {
      return unavailable("GetFieldParams: " + status.error_message());
    }
    for (const v1::FieldParam& p : params.params()) {
      if (p.name() == "self_shadow_bias") out.field.self_shadow_bias = std::stof(p.value());
      if (p.name() == "weight_crush_threshold") {
        out.field.weight_crush_threshold = std::stof(p.value());
      }
    }
    if (const std::string problem = probe_field_problem(out.field); !problem.empty()) {
      return internal_error("the server's atlases do not fit together: " + problem);
    }
    return out;
  }
  return unavailable("the field changed during each of " + std::to_string(kAttempts) +
                     " downloads (stop its streams, or retry)");
}

}  // namespace ddgi
