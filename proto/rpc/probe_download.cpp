#include "rpc/probe_download.h"

#include <algorithm>
#include <cstring>

#include "rpc/chunk_download.h"

namespace ddgi {
std::vector<float> raw_floats(const std::string& bytes) {
  std::vector<float> values(bytes.size() / sizeof(float));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(float));  // little-endian
  return values;
}

namespace {

// The field from its RAW_F32 dumps: the irradiance and distance atlases or the SH
// coefficients, then the probe states (`kinds` says which).
ProbeField field_from_dumps(const std::vector<v1::AtlasKind>& kinds,
                            const std::vector<v1::AtlasMetadata>& meta,
                            const std::vector<std::string>& bytes) {
  ProbeField f;
  const v1::AtlasMetadata& m = meta[0];
  f.counts[0] = m.probe_counts_x();
  f.counts[1] = m.probe_counts_y();
  f.counts[2] = m.probe_counts_z();
  f.origin = {m.grid_origin().x(), m.grid_origin().y(), m.grid_origin().z()};
  f.spacing = {m.probe_spacing().x(), m.probe_spacing().y(), m.probe_spacing().z()};
  for (size_t i = 0; i < kinds.size(); ++i) {
    const v1::AtlasMetadata& a = meta[i];
    switch (kinds[i]) {
      case v1::ATLAS_KIND_IRRADIANCE:
        f.irradiance_texels = a.texels_per_probe();
        f.border_texels = a.border_texels();
        f.tiles_per_row = a.tiles_per_row();
        f.irradiance_gamma = a.encoding_gamma();
        f.irradiance_width = a.width();
        f.irradiance_height = a.height();
        f.irradiance = raw_floats(bytes[i]);
        break;
      case v1::ATLAS_KIND_DISTANCE:
        f.distance_texels = a.texels_per_probe();
        f.distance_width = a.width();
        f.distance_height = a.height();
        f.distance = raw_floats(bytes[i]);
        break;
      case v1::ATLAS_KIND_SH:
        f.basis = kProbeBasisSh;
        f.sh = raw_floats(bytes[i]);
        for (int band = 0; band < 3 && band < a.sh_band_scales_size(); ++band) {
          f.sh_band_scales[band] = a.sh_band_scales(band);
        }
        break;
      default:
        f.probe_states = raw_floats(bytes[i]);
    }
  }
  return f;
}

// The field parameters the download needs: the basis and the two the query reads.
struct QueryParams {
  bool sh = false;
  float self_shadow_bias = 0.3f;
  float weight_crush_threshold = 0.2f;
};

Result<QueryParams> query_params(v1::RenderService::Stub& stub, const ContextFactory& context,
                                 const std::string& session_id) {
  v1::GetFieldParamsRequest request;
  request.set_session_id(session_id);
  v1::FieldParams params;
  const std::unique_ptr<grpc::ClientContext> call = context();
  if (const grpc::Status status = stub.GetFieldParams(call.get(), request, &params); !status.ok()) {
    return unavailable("GetFieldParams: " + status.error_message());
  }
  QueryParams out;
  for (const v1::FieldParam& p : params.params()) {
    if (p.name() == "basis") out.sh = p.value() == "sh";
    if (p.name() == "self_shadow_bias") out.self_shadow_bias = std::stof(p.value());
    if (p.name() == "weight_crush_threshold") out.weight_crush_threshold = std::stof(p.value());
  }
  return out;
}

// A whole download stream into `metadata` and `bytes`; `progress` (optional) after each chunk.
template <typename Chunk, typename Metadata>
grpc::Status collect_chunks(grpc::ClientContext& call, grpc::ClientReaderInterface<Chunk>& reader,
                            Metadata* metadata, std::string* bytes,
                            const std::function<void(uint64_t)>& progress) {
  bytes->clear();
  return read_chunks<Chunk, Metadata>(
      call, reader,
      [&](const Metadata& m) {
        *metadata = m;
        bytes->reserve(size_t(std::min<uint64_t>(m.total_bytes(), 1ull << 32)));
        return true;
      },
      [&](const std::string& data) {
        *bytes += data;
        if (progress) progress(bytes->size());
        return true;
      });
}

}  // namespace

grpc::Status fetch_atlas(v1::RenderService::Stub& stub, const ContextFactory& context,
                         const v1::DumpAtlasRequest& request, v1::AtlasMetadata* metadata,
                         std::string* bytes) {
  const std::unique_ptr<grpc::ClientContext> call = context();
  auto reader = stub.DumpAtlas(call.get(), request);
  return collect_chunks(*call, *reader, metadata, bytes, {});
}

grpc::Status fetch_scene(v1::RenderService::Stub& stub, const ContextFactory& context,
                         const v1::ExportSceneRequest& request, v1::SceneMetadata* metadata,
                         std::string* bytes, const std::function<void(uint64_t)>& progress) {
  const std::unique_ptr<grpc::ClientContext> call = context();
  auto reader = stub.ExportScene(call.get(), request);
  return collect_chunks(*call, *reader, metadata, bytes, progress);
}

Result<DownloadedField> download_probe_field(v1::RenderService::Stub& stub,
                                             const ContextFactory& context,
                                             const std::string& session_id) {
  constexpr int kAttempts = 5;
  DDGI_ASSIGN_OR_RETURN(const QueryParams params, query_params(stub, context, session_id));
  const std::vector<v1::AtlasKind> kinds =
      params.sh ? std::vector<v1::AtlasKind>{v1::ATLAS_KIND_SH, v1::ATLAS_KIND_PROBE_STATES}
                : std::vector<v1::AtlasKind>{v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_KIND_DISTANCE,
                                             v1::ATLAS_KIND_PROBE_STATES};
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    std::vector<v1::AtlasMetadata> meta(kinds.size());
    std::vector<std::string> bytes(kinds.size());
    bool one_update = true;
    for (size_t i = 0; i < kinds.size(); ++i) {
      v1::DumpAtlasRequest request;
      request.set_session_id(session_id);
      request.set_kind(kinds[i]);
      request.set_format(v1::ATLAS_FORMAT_RAW_F32);
      if (const grpc::Status status = fetch_atlas(stub, context, request, &meta[i], &bytes[i]);
          !status.ok()) {
        return unavailable("DumpAtlas: " + status.error_message());
      }
      one_update = one_update && meta[i].field_updates() == meta[0].field_updates();
    }
    if (!one_update) continue;  // an update came between two downloads
    DownloadedField out{field_from_dumps(kinds, meta, bytes), meta[0].field_updates()};
    out.field.self_shadow_bias = params.self_shadow_bias;
    out.field.weight_crush_threshold = params.weight_crush_threshold;
    if (const std::string problem = probe_field_problem(out.field); !problem.empty()) {
      return internal_error("the server's atlases do not fit together: " + problem);
    }
    return out;
  }
  return unavailable("the field changed during each of " + std::to_string(kAttempts) +
                     " downloads (stop its streams, or retry)");
}

}  // namespace ddgi
