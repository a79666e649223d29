// ddgi-client commands for the server, sessions, views, camera, lights and instances.
#include <cstdio>
#include <fstream>
#include <sstream>

#include "cli.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace ddgi::client {
namespace {

// Runs one unary call and prints the reply as JSON.
template <typename Request, typename Reply, typename Call>
int unary(Cli& cli, const Request& request, Call call) {
  Reply reply;
  auto context = cli.context();
  const grpc::Status status = call(context.get(), request, &reply);
  if (!status.ok()) return report(status);
  print_json(reply);
  return 0;
}

Result<std::string> read_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return not_found("cannot read " + path);
  std::ostringstream bytes;
  bytes << file.rdbuf();
  return bytes.str();
}

// SCENE (a library name) or --upload FILE.glb.
Result<v1::SceneSource> scene_source(const Flags& flags, size_t positional_index) {
  v1::SceneSource source;
  DDGI_ASSIGN_OR_RETURN(const std::string upload, flags.get_string("upload", ""));
  const bool has_name = flags.positional().size() > positional_index;
  if (has_name == !upload.empty()) {
    return invalid_argument("give a scene name from `info` or --upload FILE.glb (one of them)");
  }
  if (has_name) {
    source.set_name(flags.positional()[positional_index]);
  } else {
    DDGI_ASSIGN_OR_RETURN(*source.mutable_glb(), read_file(upload));
  }
  return source;
}

int info(Cli& cli) {
  return unary<v1::GetServerInfoRequest, v1::ServerInfo>(
      cli, v1::GetServerInfoRequest(),
      [&](auto* c, const auto& r, auto* out) { return cli.stub->GetServerInfo(c, r, out); });
}

int health(Cli& cli) {
  auto stub = grpc::health::v1::Health::NewStub(cli.channel);
  grpc::health::v1::HealthCheckRequest request;
  DDGI_CLI_TRY(const std::string service, cli.flags.get_string("service", ""));
  request.set_service(service);
  grpc::health::v1::HealthCheckResponse reply;
  auto context = cli.context();
  const grpc::Status status = stub->Check(context.get(), request, &reply);
  if (!status.ok()) return report(status);
  print_json(reply);
  return reply.status() == grpc::health::v1::HealthCheckResponse::SERVING ? 0 : kExitRpcError;
}

int load(Cli& cli) {
  v1::CreateSessionRequest request;
  DDGI_CLI_TRY(*request.mutable_scene(), scene_source(cli.flags, 1));
  if (cli.flags.has("gi")) {
    DDGI_CLI_TRY(const std::string gi, cli.flags.get_string("gi", "on"));
    if (gi != "on" && gi != "off") return report(invalid_argument("--gi must be on or off"));
    request.set_gi(gi == "on");
  }
  if (cli.flags.has("warmup")) {
    DDGI_CLI_TRY(const int64_t warmup, cli.flags.get_int("warmup", 0, 0, 1 << 30));
    request.set_warmup_updates(uint32_t(warmup));
  }
  for (const std::string& assignment : cli.flags.get_all("field")) {
    const auto equals = assignment.find('=');
    if (equals == std::string::npos) {
      return report(invalid_argument("--field expects NAME=VALUE (got '" + assignment + "')"));
    }
    auto* p = request.add_field_params();
    p->set_name(assignment.substr(0, equals));
    p->set_value(assignment.substr(equals + 1));
  }
  if (cli.flags.has("direct")) {
    DDGI_CLI_TRY(const std::string direct, cli.flags.get_string("direct", ""));
    if (direct == "shadow-rays") {
      request.set_direct_mode(v1::DIRECT_MODE_SHADOW_RAYS);
    } else if (direct == "unshadowed") {
      request.set_direct_mode(v1::DIRECT_MODE_UNSHADOWED);
    } else if (direct == "shadow-field") {
      request.set_direct_mode(v1::DIRECT_MODE_SHADOW_FIELD);
    } else if (direct == "ao") {
      request.set_direct_mode(v1::DIRECT_MODE_AMBIENT_OCCLUSION);
    } else if (direct == "ao-traced") {
      request.set_direct_mode(v1::DIRECT_MODE_AO_TRACED);
    } else if (direct == "ao-cache") {
      request.set_direct_mode(v1::DIRECT_MODE_AO_CACHE);
    } else {
      return report(invalid_argument(
          "--direct must be shadow-rays, unshadowed, shadow-field, ao, ao-traced or ao-cache"));
    }
  }
  for (const std::string& assignment : cli.flags.get_all("shadow-field")) {
    const auto equals = assignment.find('=');
    if (equals == std::string::npos) {
      return report(
          invalid_argument("--shadow-field expects NAME=VALUE (got '" + assignment + "')"));
    }
    auto* p = request.add_shadow_field_params();
    p->set_name(assignment.substr(0, equals));
    p->set_value(assignment.substr(equals + 1));
  }
  return unary<v1::CreateSessionRequest, v1::SessionInfo>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->CreateSession(c, r, out); });
}

int reload(Cli& cli) {
  v1::LoadSceneRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(*request.mutable_scene(), scene_source(cli.flags, 1));
  if (cli.flags.has("warmup")) {
    DDGI_CLI_TRY(const int64_t warmup, cli.flags.get_int("warmup", 0, 0, 1 << 30));
    request.set_warmup_updates(uint32_t(warmup));
  }
  return unary<v1::LoadSceneRequest, v1::SessionInfo>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->LoadScene(c, r, out); });
}

int close_session(Cli& cli) {
  v1::CloseSessionRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  return unary<v1::CloseSessionRequest, v1::CloseSessionReply>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->CloseSession(c, r, out); });
}

int sessions(Cli& cli) {
  return unary<v1::ListSessionsRequest, v1::ListSessionsReply>(
      cli, v1::ListSessionsRequest(),
      [&](auto* c, const auto& r, auto* out) { return cli.stub->ListSessions(c, r, out); });
}

int session(Cli& cli) {
  v1::GetSessionRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  return unary<v1::GetSessionRequest, v1::SessionInfo>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->GetSession(c, r, out); });
}

Result<std::string> view_flag(const Flags& flags) {
  DDGI_ASSIGN_OR_RETURN(const std::string view, flags.get_string("view", ""));
  if (view.empty()) return invalid_argument("--view ID is required");
  return view;
}

int view_create(Cli& cli) {
  v1::CreateViewRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(*request.mutable_settings(), view_settings_flags(cli.flags));
  DDGI_CLI_TRY(const auto camera, camera_flags(cli.flags));
  if (camera) *request.mutable_camera() = *camera;
  return unary<v1::CreateViewRequest, v1::ViewInfo>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->CreateView(c, r, out); });
}

int view_update(Cli& cli) {
  v1::UpdateViewRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(*request.mutable_view_id(), view_flag(cli.flags));
  DDGI_CLI_TRY(*request.mutable_settings(), view_settings_flags(cli.flags));
  return unary<v1::UpdateViewRequest, v1::ViewInfo>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->UpdateView(c, r, out); });
}

int view_delete(Cli& cli) {
  v1::DeleteViewRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(*request.mutable_view_id(), view_flag(cli.flags));
  return unary<v1::DeleteViewRequest, v1::DeleteViewReply>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->DeleteView(c, r, out); });
}

int camera(Cli& cli) {
  v1::SetCameraRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  DDGI_CLI_TRY(*request.mutable_view_id(), view_flag(cli.flags));
  DDGI_CLI_TRY(const auto camera, camera_flags(cli.flags));
  if (!camera) return report(invalid_argument("--camera px,py,pz,tx,ty,tz[,fov] is required"));
  *request.mutable_camera() = *camera;
  return unary<v1::SetCameraRequest, v1::ViewInfo>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->SetCamera(c, r, out); });
}

// The light flags given; the server fills in or keeps the rest.
Result<v1::Light> light_flags(const Flags& flags) {
  v1::Light light;
  if (flags.has("type")) {
    DDGI_ASSIGN_OR_RETURN(const std::string type, flags.get_string("type", ""));
    if (type == "point") {
      light.set_type(v1::LIGHT_TYPE_POINT);
    } else if (type == "spot") {
      light.set_type(v1::LIGHT_TYPE_SPOT);
    } else if (type == "directional") {
      light.set_type(v1::LIGHT_TYPE_DIRECTIONAL);
    } else {
      return invalid_argument("--type must be point, spot or directional (got '" + type + "')");
    }
  }
  if (flags.has("name")) {
    DDGI_ASSIGN_OR_RETURN(*light.mutable_name(), flags.get_string("name", ""));
  }
  if (flags.has("color")) {
    DDGI_ASSIGN_OR_RETURN(*light.mutable_color(), vec3_flag(flags, "color"));
  }
  if (flags.has("position")) {
    DDGI_ASSIGN_OR_RETURN(*light.mutable_position(), vec3_flag(flags, "position"));
  }
  if (flags.has("direction")) {
    DDGI_ASSIGN_OR_RETURN(*light.mutable_direction(), vec3_flag(flags, "direction"));
  }
  // Range checks are the server's; NaN and Inf are refused here already by the flag parser.
  const std::pair<const char*, void (v1::Light::*)(float)> scalars[] = {
      {"intensity", &v1::Light::set_intensity},
      {"range", &v1::Light::set_range},
      {"radius", &v1::Light::set_radius},
      {"inner-cone", &v1::Light::set_inner_cone_degrees},
      {"outer-cone", &v1::Light::set_outer_cone_degrees}};
  for (const auto& [name, setter] : scalars) {
    if (!flags.has(name)) continue;
    DDGI_ASSIGN_OR_RETURN(const double value, flags.get_double(name, 0.0, -1e30, 1e30));
    (light.*setter)(float(value));
  }
  return light;
}

Result<uint32_t> light_id_flag(const Flags& flags) {
  if (!flags.has("id")) return invalid_argument("--id N (a light id from `session`) is required");
  DDGI_ASSIGN_OR_RETURN(const int64_t id, flags.get_int("id", 0, 0, 0xffffffffll));
  return uint32_t(id);
}

int light(Cli& cli) {
  const auto& args = cli.flags.positional();
  const std::string action = args.size() > 1 ? args[1] : "";
  if (action == "add") {
    v1::AddLightRequest request;
    DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
    DDGI_CLI_TRY(*request.mutable_light(), light_flags(cli.flags));
    return unary<v1::AddLightRequest, v1::LightReply>(
        cli, request,
        [&](auto* c, const auto& r, auto* out) { return cli.stub->AddLight(c, r, out); });
  }
  if (action == "update") {
    v1::UpdateLightRequest request;
    DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
    DDGI_CLI_TRY(const uint32_t id, light_id_flag(cli.flags));
    request.set_light_id(id);
    DDGI_CLI_TRY(*request.mutable_light(), light_flags(cli.flags));
    return unary<v1::UpdateLightRequest, v1::LightReply>(
        cli, request,
        [&](auto* c, const auto& r, auto* out) { return cli.stub->UpdateLight(c, r, out); });
  }
  if (action == "remove") {
    v1::RemoveLightRequest request;
    DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
    DDGI_CLI_TRY(const uint32_t id, light_id_flag(cli.flags));
    request.set_light_id(id);
    return unary<v1::RemoveLightRequest, v1::LightReply>(
        cli, request,
        [&](auto* c, const auto& r, auto* out) { return cli.stub->RemoveLight(c, r, out); });
  }
  return report(invalid_argument("light needs add, update or remove (got '" + action + "')"));
}

int transform(Cli& cli) {
  v1::SetInstanceTransformRequest request;
  DDGI_CLI_TRY(*request.mutable_session_id(), session_flag(cli.flags));
  if (!cli.flags.has("instance")) {
    return report(invalid_argument("--instance N (an index from `session`) is required"));
  }
  DDGI_CLI_TRY(const int64_t index, cli.flags.get_int("instance", 0, 0, 0xffffffffll));
  request.set_instance_index(uint32_t(index));
  if (cli.flags.has("matrix") == cli.flags.has("translate")) {
    return report(invalid_argument(
        "give --matrix m0,...,m15 (column-major) or --translate x,y,z [--scale s] (one of them)"));
  }
  std::vector<double> m;
  if (cli.flags.has("matrix")) {
    DDGI_CLI_TRY(m, cli.flags.get_doubles("matrix", 16, 16));
  } else {
    DDGI_CLI_TRY(const std::vector<double> t, cli.flags.get_doubles("translate", 3, 3));
    DDGI_CLI_TRY(const double s, cli.flags.get_double("scale", 1.0, -1e30, 1e30));
    m = {s, 0, 0, 0, 0, s, 0, 0, 0, 0, s, 0, t[0], t[1], t[2], 1};
  }
  for (double value : m) request.mutable_transform()->add_m(float(value));
  return unary<v1::SetInstanceTransformRequest, v1::InstanceReply>(
      cli, request,
      [&](auto* c, const auto& r, auto* out) { return cli.stub->SetInstanceTransform(c, r, out); });
}

}  // namespace

void add_session_commands(std::vector<CommandSpec>& commands) {
  commands.push_back({"info", "", "server, GPU, limits and scene library", {}, {}, info});
  commands.push_back({"health",
                      "[--service NAME]",
                      "gRPC health check; exit 0 when SERVING",
                      {"service"},
                      {},
                      health});
  commands.push_back(
      {"load",
       "SCENE | --upload FILE.glb [--gi on|off] [--warmup N] [--field NAME=VALUE]... "
       "[--direct shadow-rays|unshadowed|shadow-field|ao|ao-traced|ao-cache] "
       "[--shadow-field NAME=VALUE]...",
       "create a session on a library scene or an uploaded .glb",
       {"upload", "gi", "warmup", "field", "direct", "shadow-field"},
       {},
       load});
  commands.push_back({"reload",
                      "--session ID SCENE | --upload FILE.glb [--warmup N]",
                      "replace a session's scene",
                      {"session", "upload", "warmup"},
                      {},
                      reload});
  commands.push_back({"close",
                      "--session ID",
                      "close a session, freeing its GPU memory",
                      {"session"},
                      {},
                      close_session});
  commands.push_back({"sessions", "", "list sessions", {}, {}, sessions});
  commands.push_back({"session",
                      "--session ID",
                      "a session's scene, lights, instances, views and field",
                      {"session"},
                      {},
                      session});
  std::vector<std::string> view_flags = view_setting_flag_names();
  view_flags.push_back("session");
  commands.push_back({"view-create",
                      "--session ID [--width N --height N --camera px,py,pz,tx,ty,tz[,fov] --up "
                      "x,y,z --exposure X --tonemap T --view-mode M --quality Q]",
                      "add a view (a camera) to a session",
                      view_flags,
                      {},
                      view_create});
  std::vector<std::string> update_flags = view_flags;
  update_flags.push_back("view");
  commands.push_back({"view-update",
                      "--session ID --view V [settings as view-create]",
                      "change a view's size, exposure, tone map, mode or JPEG quality",
                      update_flags,
                      {},
                      view_update});
  commands.push_back({"view-delete",
                      "--session ID --view V",
                      "remove a view",
                      {"session", "view"},
                      {},
                      view_delete});
  commands.push_back({"camera",
                      "--session ID --view V --camera px,py,pz,tx,ty,tz[,fov] [--up x,y,z]",
                      "move a view's camera",
                      {"session", "view", "camera", "up"},
                      {},
                      camera});
  commands.push_back({"light",
                      "add|update|remove --session ID [--id N] [--type point|spot|directional] "
                      "[--color r,g,b] [--intensity X] [--position x,y,z] [--direction x,y,z] "
                      "[--range X] [--radius X] [--inner-cone DEG] [--outer-cone DEG] [--name N]",
                      "add, change or remove a light",
                      {"session", "id", "type", "name", "color", "intensity", "position",
                       "direction", "range", "radius", "inner-cone", "outer-cone"},
                      {},
                      light});
  commands.push_back({"transform",
                      "--session ID --instance N (--matrix m0,...,m15 | --translate x,y,z "
                      "[--scale s])",
                      "move an instance",
                      {"session", "instance", "matrix", "translate", "scale"},
                      {},
                      transform});
}

}  // namespace ddgi::client
