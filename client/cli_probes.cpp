// ddgi-client commands that shade from downloaded probes: `probes` saves a session's
// irradiance field as one file (rpc/probe_file.h), `probe-stream` receives it as StreamProbes
// sends it (rpc/probe_stream.h) and reports the bytes, `irradiance` evaluates a saved field at
// points with the server's own formula (rpc/probe_field.h), with no server involved.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

#include "cli.h"
#include "rpc/probe_download.h"
#include "rpc/probe_file.h"
#include "rpc/probe_stream.h"

namespace ddgi::client {
namespace {

Status write_probe_file(const std::string& path, const ProbeFile& file) {
  const std::string bytes = encode_probe_file(file);
  std::ofstream stream(path, std::ios::binary);
  stream.write(bytes.data(), std::streamsize(bytes.size()));
  return stream ? ok_status() : unavailable("cannot write " + path);
}

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
  if (Status written = write_probe_file(out, file); !written.ok()) return report(written.error());
  const size_t bytes = encode_probe_file(file).size();
  const int probes = file.field.counts[0] * file.field.counts[1] * file.field.counts[2];
  std::printf(
      "{\n  \"out\": \"%s\",\n  \"probes\": %d,\n  \"bytes\": %zu,\n"
      "  \"bytes_per_probe\": %.1f,\n  \"field_updates\": %llu\n}\n",
      out.c_str(), probes, bytes, double(bytes) / probes,
      static_cast<unsigned long long>(file.field_updates));
  return 0;
}

// Bytes of the stream's messages, full and delta apart.
struct StreamBytes {
  uint64_t full_messages = 0, full_bytes = 0, delta_messages = 0, delta_bytes = 0, delta_probes = 0,
           folded = 0;
};

int probe_stream(Cli& cli) {
  v1::StreamProbesRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(const int64_t messages, cli.flags.get_int("messages", 10, 1, 1ll << 40));
  DDGI_CLI_TRY(const double threshold, cli.flags.get_double("threshold", 0.0, 0.0, 1.0));
  DDGI_CLI_TRY(const int64_t refresh, cli.flags.get_int("refresh", 0, 0, 100000));
  DDGI_CLI_TRY(const double stall, cli.flags.get_double("stall-seconds", 0.0, 0.0, 3600.0));
  DDGI_CLI_TRY(const std::string out, cli.flags.get_string("out", ""));
  request.set_change_threshold(float(threshold));
  request.set_full_refresh_interval(uint32_t(refresh));
  const std::unique_ptr<grpc::ClientContext> context = cli.context(false);
  auto reader = cli.stub->StreamProbes(context.get(), request);
  StreamedField streamed;
  StreamBytes bytes;
  v1::ProbeUpdate update;
  const auto start = std::chrono::steady_clock::now();
  while (int64_t(streamed.messages) < messages && reader->Read(&update)) {
    // --stall-seconds: a slow reader, after the first message.
    if (streamed.messages == 1 && stall > 0.0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(stall));
    }
    if (Status applied = apply_probe_update(update, &streamed); !applied.ok()) {
      context->TryCancel();
      (void)reader->Finish();
      return report(applied.error());
    }
    const uint64_t size = update.ByteSizeLong();
    (update.full() ? bytes.full_messages : bytes.delta_messages) += 1;
    (update.full() ? bytes.full_bytes : bytes.delta_bytes) += size;
    if (!update.full()) bytes.delta_probes += update.values().size() / 2 / streamed.stride;
    bytes.folded += update.updates_folded();
  }
  context->TryCancel();
  const grpc::Status status = reader->Finish();
  if (int64_t(streamed.messages) < messages) {
    if (!status.ok()) return report(status);
    return report(
        unavailable("the stream ended after " + std::to_string(streamed.messages) + " messages"));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!out.empty()) {
    const ProbeFile file{streamed.field, streamed.field_updates, request.session_id()};
    if (Status written = write_probe_file(out, file); !written.ok()) {
      return report(written.error());
    }
  }
  const double probes = double(streamed.field.probe_states.size() / kProbeStateValues);
  const auto per = [](uint64_t total, uint64_t count) {
    return count ? double(total) / double(count) : 0.0;
  };
  std::printf(
      "{\n  \"messages\": %llu,\n  \"probes\": %.0f,\n  \"field_updates\": %llu,\n"
      "  \"full_messages\": %llu,\n  \"full_bytes_per_message\": %.0f,\n"
      "  \"full_bytes_per_probe\": %.2f,\n  \"delta_messages\": %llu,\n"
      "  \"delta_bytes_per_message\": %.0f,\n  \"delta_probes_per_message\": %.1f,\n"
      "  \"updates_folded\": %llu,\n  \"seconds\": %.3f\n}\n",
      static_cast<unsigned long long>(streamed.messages), probes,
      static_cast<unsigned long long>(streamed.field_updates),
      static_cast<unsigned long long>(bytes.full_messages),
      per(bytes.full_bytes, bytes.full_messages),
      per(bytes.full_bytes, bytes.full_messages) / std::max(probes, 1.0),
      static_cast<unsigned long long>(bytes.delta_messages),
      per(bytes.delta_bytes, bytes.delta_messages), per(bytes.delta_probes, bytes.delta_messages),
      static_cast<unsigned long long>(bytes.folded), seconds);
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
  commands.push_back(
      {"probes",
       "--session ID --out FILE",
       "save the session's irradiance field (probe grid, atlases or SH, states) as one "
       "file for `irradiance` and the web client (docs/probe-files.md)",
       {"session", "out"},
       {},
       probes});
  commands.push_back({"probe-stream",
                      "--session ID [--messages N] [--threshold T] [--refresh N] "
                      "[--stall-seconds S] [--out FILE]",
                      "receive the field as StreamProbes sends it (N messages), report the bytes "
                      "of full and delta messages, save the result as a probes file",
                      {"session", "messages", "threshold", "refresh", "stall-seconds", "out"},
                      {},
                      probe_stream});
  commands.push_back({"irradiance",
                      "--probes FILE --points 'px,py,pz,nx,ny,nz;...' | --points-file FILE",
                      "field irradiance (E/pi) at points from a probes file, computed here as "
                      "the server's query does; needs no server",
                      {"probes", "points", "points-file"},
                      {},
                      irradiance});
}

}  // namespace ddgi::client
