// ddgi-client commands that shade from downloaded probes: `probes` saves a session's
// irradiance field as one file (probe_file.h), `irradiance` evaluates it at points with the
// server's own formula (rpc/probe_field.h), with no server involved.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cli.h"
#include "probe_file.h"

namespace ddgi::client {
namespace {

// The field's three atlases and the two parameters the query reads, downloaded until all three
// atlases come from the same field update (a session streaming frames updates it meanwhile).
Result<ProbeFile> download_probes(const Cli& cli, const std::string& session) {
  constexpr int kAttempts = 5;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    ProbeFile file;
    file.session_id = session;
    ProbeField& f = file.field;
    v1::AtlasMetadata meta[3];
    std::string bytes[3];
    const v1::AtlasKind kinds[3] = {v1::ATLAS_KIND_IRRADIANCE, v1::ATLAS_KIND_DISTANCE,
                                    v1::ATLAS_KIND_PROBE_STATES};
    for (int i = 0; i < 3; ++i) {
      v1::DumpAtlasRequest request;
      request.set_session_id(session);
      request.set_kind(kinds[i]);
      request.set_format(v1::ATLAS_FORMAT_RAW_F32);
      if (const grpc::Status status = fetch_atlas(cli, request, &meta[i], &bytes[i]);
          !status.ok()) {
        return unavailable("DumpAtlas: " + status.error_message());
      }
    }
    if (meta[0].field_updates() != meta[1].field_updates() ||
        meta[1].field_updates() != meta[2].field_updates()) {
      continue;  // an update came between two downloads
    }
    auto floats = [](const std::string& b) {
      std::vector<float> v(b.size() / 4);
      std::memcpy(v.data(), b.data(), v.size() * 4);
      return v;
    };
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
    f.irradiance = floats(bytes[0]);
    f.distance_texels = meta[1].texels_per_probe();
    f.distance_width = meta[1].width();
    f.distance_height = meta[1].height();
    f.distance = floats(bytes[1]);
    f.probe_states = floats(bytes[2]);
    file.field_updates = m.field_updates();

    v1::GetFieldParamsRequest request;
    request.set_session_id(session);
    v1::FieldParams params;
    auto context = cli.context();
    if (const grpc::Status status = cli.stub->GetFieldParams(context.get(), request, &params);
        !status.ok()) {
      return unavailable("GetFieldParams: " + status.error_message());
    }
    for (const v1::FieldParam& p : params.params()) {
      if (p.name() == "self_shadow_bias") f.self_shadow_bias = std::stof(p.value());
      if (p.name() == "weight_crush_threshold") f.weight_crush_threshold = std::stof(p.value());
    }
    if (const std::string problem = probe_field_problem(f); !problem.empty()) {
      return internal_error("the server's atlases do not fit together: " + problem);
    }
    return file;
  }
  return unavailable("the field changed during each of " + std::to_string(kAttempts) +
                     " downloads (stop its streams, or retry)");
}

int probes(Cli& cli) {
  DDGI_CLI_TRY(const std::string session, session_flag(cli.flags));
  DDGI_CLI_TRY(const std::string out, cli.flags.get_string("out", ""));
  if (out.empty()) return report(invalid_argument("--out FILE is required"));
  DDGI_CLI_TRY(const ProbeFile file, download_probes(cli, session));
  const std::string bytes = encode_probe_file(file);
  std::ofstream stream(out, std::ios::binary);
  stream.write(bytes.data(), std::streamsize(bytes.size()));
  if (!stream) return report(unavailable("cannot write " + out));
  const int probes = file.field.counts[0] * file.field.counts[1] * file.field.counts[2];
  std::printf(
      "{\n  \"out\": \"%s\",\n  \"probes\": %d,\n  \"bytes\": %zu,\n"
      "  \"bytes_per_probe\": %.1f,\n  \"field_updates\": %llu\n}\n",
      out.c_str(), probes, bytes.size(), double(bytes.size()) / probes,
      static_cast<unsigned long long>(file.field_updates));
  return 0;
}

int irradiance(Cli& cli) {
  DDGI_CLI_TRY(const std::string path, cli.flags.get_string("probes", ""));
  if (path.empty()) return report(invalid_argument("--probes FILE is required"));
  std::ifstream in(path, std::ios::binary);
  if (!in) return report(not_found("cannot read " + path));
  std::ostringstream content;
  content << in.rdbuf();
  DDGI_CLI_TRY(const ProbeFile file, decode_probe_file(content.str()));
  DDGI_CLI_TRY(const std::vector<v1::QueryPoint> points, points_flags(cli.flags));
  // The reply in QueryIrradiance's own shape, so a script can compare the two.
  v1::QueryIrradianceReply reply;
  reply.set_field_updates(file.field_updates);
  for (const v1::QueryPoint& point : points) {
    const ProbeVec3 normal = {point.normal().x(), point.normal().y(), point.normal().z()};
    const ProbeVec3 e = probe_field_irradiance(
        file.field, {point.position().x(), point.position().y(), point.position().z()}, normal,
        normal);
    v1::Vec3* out = reply.add_irradiance();
    out->set_x(e.x);
    out->set_y(e.y);
    out->set_z(e.z);
  }
  print_json(reply);
  return 0;
}

}  // namespace

void add_probe_commands(std::vector<CommandSpec>& commands) {
  commands.push_back({"probes",
                      "--session ID --out FILE",
                      "save the session's irradiance field (probe grid, atlases, states) as one "
                      "file for `irradiance` and the web client (docs/probe-files.md)",
                      {"session", "out"},
                      {},
                      probes});
  commands.push_back({"irradiance",
                      "--probes FILE --points 'px,py,pz,nx,ny,nz;...' | --points-file FILE",
                      "field irradiance (E/pi) at points from a probes file, computed here as "
                      "the server's query does; needs no server",
                      {"probes", "points", "points-file"},
                      {},
                      irradiance});
}

}  // namespace ddgi::client
