// ddgi-client commands for the irradiance field: parameters, atlas dumps, irradiance queries.
#include <cstdio>
#include <fstream>
#include <sstream>

#include "atlas_convert.h"
#include "cli.h"
#include "encode/file_io.h"
#include "rpc/probe_download.h"

namespace ddgi::client {
namespace {

int params(Cli& cli) {
  const auto& args = cli.flags.positional();
  const std::string action = args.size() > 1 ? args[1] : "";
  DDGI_CLI_TRY(const std::string session, session_flag(cli.flags));
  DDGI_CLI_TRY(const std::string field, cli.flags.get_string("field", "irradiance"));
  if (field != "irradiance" && field != "shadow") {
    return report(invalid_argument("--field must be irradiance or shadow (got '" + field + "')"));
  }
  const v1::FieldKind kind = field == "shadow" ? v1::FIELD_KIND_SHADOW : v1::FIELD_KIND_IRRADIANCE;
  v1::FieldParams reply;
  auto context = cli.context();
  grpc::Status status;
  if (action == "get") {
    if (args.size() > 2) return report(invalid_argument("params get takes no NAME=VALUE"));
    v1::GetFieldParamsRequest request;
    request.set_session_id(session);
    request.set_field(kind);
    status = cli.stub->GetFieldParams(context.get(), request, &reply);
  } else if (action == "set") {
    v1::SetFieldParamsRequest request;
    request.set_session_id(session);
    request.set_field(kind);
    for (size_t i = 2; i < args.size(); ++i) {
      const auto equals = args[i].find('=');
      if (equals == std::string::npos) {
        return report(invalid_argument("params set expects NAME=VALUE (got '" + args[i] + "')"));
      }
      auto* p = request.add_params();
      p->set_name(args[i].substr(0, equals));
      p->set_value(args[i].substr(equals + 1));
    }
    if (request.params().empty()) {
      return report(invalid_argument("params set needs at least one NAME=VALUE"));
    }
    status = cli.stub->SetFieldParams(context.get(), request, &reply);
  } else {
    return report(invalid_argument("params needs get or set (got '" + action + "')"));
  }
  if (!status.ok()) return report(status);
  print_json(reply);
  return 0;
}

Result<v1::AtlasKind> kind_flag(const Flags& flags) {
  DDGI_ASSIGN_OR_RETURN(const std::string kind, flags.get_string("kind", "irradiance"));
  if (kind == "irradiance") return v1::ATLAS_KIND_IRRADIANCE;
  if (kind == "distance") return v1::ATLAS_KIND_DISTANCE;
  if (kind == "shadow") return v1::ATLAS_KIND_SHADOW;
  if (kind == "shadow-moments") return v1::ATLAS_KIND_SHADOW_MOMENTS;
  if (kind == "probe-states") return v1::ATLAS_KIND_PROBE_STATES;
  if (kind == "sh") return v1::ATLAS_KIND_SH;
  return invalid_argument(
      "--kind must be irradiance, distance, shadow, shadow-moments, probe-states or sh (got '" +
      kind + "')");
}

int atlas(Cli& cli) {
  v1::DumpAtlasRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(const v1::AtlasKind kind, kind_flag(cli.flags));
  request.set_kind(kind);
  DDGI_CLI_TRY(const int64_t volume, cli.flags.get_int("volume", 0, 0, 1ll << 31));
  request.set_volume(static_cast<uint32_t>(volume));
  DDGI_CLI_TRY(const std::string format, cli.flags.get_string("format", "exr"));
  if (format == "exr") {
    request.set_format(v1::ATLAS_FORMAT_EXR);
  } else if (format == "raw") {
    request.set_format(v1::ATLAS_FORMAT_RAW_F32);
  } else {
    return report(invalid_argument("--format must be exr or raw (got '" + format + "')"));
  }
  DDGI_CLI_TRY(const std::string out, cli.flags.get_string("out", ""));
  if (out.empty()) return report(invalid_argument("--out FILE is required (.exr or .raw)"));
  DDGI_CLI_TRY(const std::string convert, cli.flags.get_string("convert", ""));

  v1::AtlasMetadata metadata;
  std::string bytes;
  if (const grpc::Status status = fetch_atlas(
          *cli.stub, [&cli] { return cli.context(); }, request, &metadata, &bytes);
      !status.ok()) {
    return report(status);
  }
  {
    std::ofstream file(out, std::ios::binary);
    file.write(bytes.data(), std::streamsize(bytes.size()));
    if (!file) return report(unavailable("cannot write " + out));
    // The metadata beside the dump: for raw floats it is the only description.
    std::ofstream json(out + ".json");
    json << to_json(metadata);
    if (!json) return report(unavailable("cannot write " + out + ".json"));
  }
  if (!convert.empty()) {
    DDGI_CLI_TRY(const AtlasTexels texels, atlas_texels(metadata, bytes, out));
    if (Status converted = convert_atlas(texels, kind, convert); !converted.ok()) {
      return report(converted.error());
    }
  }
  print_json(metadata);
  return 0;
}

// The session's scene as .glb; progress on stderr in tenths of the size.
int export_scene(Cli& cli) {
  v1::ExportSceneRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(const std::string out, cli.flags.get_string("out", ""));
  if (out.empty()) return report(invalid_argument("--out FILE.glb is required"));
  v1::SceneMetadata metadata;
  std::string bytes;
  int shown = 0;
  auto progress = [&](uint64_t received) {
    const int tenth = int(10 * received / std::max<uint64_t>(metadata.total_bytes(), 1));
    if (tenth <= shown) return;
    shown = tenth;
    std::fprintf(stderr, "ddgi-client: export-scene: %.1f of %.1f MB\n", double(received) / 1e6,
                 double(metadata.total_bytes()) / 1e6);
  };
  if (const grpc::Status status = fetch_scene(
          *cli.stub, [&cli] { return cli.context(); }, request, &metadata, &bytes, progress);
      !status.ok()) {
    return report(status);
  }
  if (Status written = encode::write_file(
          out, std::span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
      !written.ok()) {
    return report(written.error());
  }
  print_json(metadata);
  return 0;
}

// "px,py,pz,nx,ny,nz" per point, points separated by ';' or new lines.
Result<std::vector<v1::QueryPoint>> parse_points(const std::string& text) {
  std::vector<v1::QueryPoint> points;
  std::string item;
  std::istringstream stream(text);
  while (std::getline(stream, item, ';')) {
    std::istringstream lines(item);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      std::vector<double> v;
      std::istringstream fields(line);
      std::string field;
      while (std::getline(fields, field, ',')) {
        DDGI_ASSIGN_OR_RETURN(const double value, parse_double(field, "query point value"));
        v.push_back(value);
      }
      if (v.size() != 6) {
        return invalid_argument("a query point is px,py,pz,nx,ny,nz (got '" + line + "')");
      }
      v1::QueryPoint point;
      point.mutable_position()->set_x(float(v[0]));
      point.mutable_position()->set_y(float(v[1]));
      point.mutable_position()->set_z(float(v[2]));
      point.mutable_normal()->set_x(float(v[3]));
      point.mutable_normal()->set_y(float(v[4]));
      point.mutable_normal()->set_z(float(v[5]));
      points.push_back(point);
    }
  }
  return points;
}

int query(Cli& cli) {
  v1::QueryIrradianceRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(const std::vector<v1::QueryPoint> points, points_flags(cli.flags));
  for (const v1::QueryPoint& point : points) *request.add_points() = point;
  if (cli.flags.has("volume")) {
    DDGI_CLI_TRY(const int64_t volume, cli.flags.get_int("volume", 0, 0, 1ll << 31));
    request.set_volume(static_cast<uint32_t>(volume));
  }
  v1::QueryIrradianceReply reply;
  auto context = cli.context();
  const grpc::Status status = cli.stub->QueryIrradiance(context.get(), request, &reply);
  if (!status.ok()) return report(status);
  print_json(reply);
  return 0;
}

}  // namespace

Result<std::vector<v1::QueryPoint>> points_flags(const Flags& flags) {
  DDGI_ASSIGN_OR_RETURN(std::string text, flags.get_string("points", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string file, flags.get_string("points-file", ""));
  if (!file.empty()) {
    DDGI_ASSIGN_OR_RETURN(const std::string content, read_text(file, "points file"));
    text += "\n" + content;
  }
  DDGI_ASSIGN_OR_RETURN(std::vector<v1::QueryPoint> points, parse_points(text));
  if (points.empty()) {
    return invalid_argument("give --points 'px,py,pz,nx,ny,nz;...' or --points-file");
  }
  return points;
}

void add_field_commands(std::vector<CommandSpec>& commands) {
  commands.push_back({"params",
                      "get|set --session ID [--field irradiance|shadow] [NAME=VALUE ...]",
                      "read or change a field's parameters (the reply has every value in effect)",
                      {"session", "field"},
                      {},
                      params});
  commands.push_back(
      {"atlas",
       "--session ID [--kind irradiance|distance|shadow|shadow-moments|probe-states|sh] "
       "[--volume V] [--format exr|raw] --out FILE [--convert FILE.png|.tif|...]",
       "dump a probe atlas (metadata to stdout and FILE.json), of volume V of a field of "
       "cascades (0, the finest, by default), optionally converted through OpenImageIO",
       {"session", "kind", "volume", "format", "out", "convert"},
       {},
       atlas});
  commands.push_back({"export-scene",
                      "--session ID --out FILE.glb",
                      "the session's scene as it is now (transforms, lights) as binary glTF",
                      {"session", "out"},
                      {},
                      export_scene});
  commands.push_back({"query",
                      "--session ID --points 'px,py,pz,nx,ny,nz;...' | --points-file FILE "
                      "[--volume V]",
                      "field irradiance (E/pi) at points: the field's blend, or volume V of a "
                      "field of cascades alone",
                      {"session", "points", "points-file", "volume"},
                      {},
                      query});
}

}  // namespace ddgi::client
