// ddgi-client commands that shade from downloaded probes: `probes` saves a session's
// irradiance field as one file (rpc/probe_file.h), `irradiance` evaluates it at points with the
// server's own formula (rpc/probe_field.h), with no server involved.
#include <cstdio>
#include <fstream>

#include "cli.h"
#include "rpc/probe_download.h"
#include "rpc/probe_file.h"

namespace ddgi::client {
namespace {

int probes(Cli& cli) {
  DDGI_CLI_TRY(const std::string session, session_flag(cli.flags));
  DDGI_CLI_TRY(const std::string out, cli.flags.get_string("out", ""));
  if (out.empty()) return report(invalid_argument("--out FILE is required"));
  DDGI_CLI_TRY(DownloadedField downloaded,
               download_probe_field(
                   *cli.stub, [&cli] { return cli.context(); }, session));
  ProbeFile file;
  file.field = std::move(downloaded.field);
  file.field_updates = downloaded.field_updates;
  file.session_id = session;
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
  DDGI_CLI_TRY(const std::string bytes, read_text(path, "probes file"));
  DDGI_CLI_TRY(const ProbeFile file, decode_probe_file(bytes));
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
                      "save the session's irradiance field (probe grid, atlases or SH, states) as one "
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
