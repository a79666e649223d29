// ddgi-client's shared pieces: the command context, JSON output, error reporting, and parsers
// for the value flags that several commands take (vectors, cameras, view settings).
#pragma once

#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "connection.h"
#include "core/flags.h"
#include "core/result.h"
#include "ddgi/v1/render_service.grpc.pb.h"

namespace ddgi::client {

// Exit codes: 0 success, 1 the server said no (or could not be reached), 2 bad usage.
inline constexpr int kExitRpcError = 1;
inline constexpr int kExitUsage = 2;

struct Cli {
  const Flags& flags;  // the command's flags (connection flags included)
  ConnectionOptions connection;
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::RenderService::Stub> stub;

  // A context with the token and the unary deadline.
  std::unique_ptr<grpc::ClientContext> context(bool deadline = true) const;
};

struct CommandSpec {
  std::string name;
  std::string usage;  // one line of arguments and flags
  std::string help;   // what it does
  std::vector<std::string> flags;
  std::vector<std::string> boolean_flags;
  std::function<int(Cli&)> run;
};

// DDGI_CLI_TRY(auto x, make_x()): in a command, a local error is reported and returned.
#define DDGI_CLI_TRY(lhs, expr) DDGI_CLI_TRY_IMPL(DDGI_CONCAT(ddgi_cli_, __LINE__), lhs, expr)
#define DDGI_CLI_TRY_IMPL(tmp, lhs, expr)                    \
  auto tmp = (expr);                                         \
  if (!tmp.ok()) return ::ddgi::client::report(tmp.error()); \
  lhs = std::move(tmp).value()

// Every command, grouped by file.
void add_session_commands(std::vector<CommandSpec>& commands);
void add_frame_commands(std::vector<CommandSpec>& commands);
void add_field_commands(std::vector<CommandSpec>& commands);
void add_probe_commands(std::vector<CommandSpec>& commands);

// "px,py,pz,nx,ny,nz" per point, points separated by ';' or new lines: --points, and the
// file --points-file names.
Result<std::vector<v1::QueryPoint>> points_flags(const Flags& flags);

// Output: one JSON document on stdout (proto field names, every field shown).
std::string to_json(const google::protobuf::Message& message);
void print_json(const google::protobuf::Message& message);
// Prints {"error": {...}} on stdout and the message on stderr; returns the exit code.
int report(const grpc::Status& status);
int report(const Error& error);

// --session, required.
Result<std::string> session_flag(const Flags& flags);
// "x,y,z"
Result<v1::Vec3> vec3_flag(const Flags& flags, const std::string& name);
// --camera px,py,pz,tx,ty,tz[,fov] (position, target, vertical FOV in degrees) and --up x,y,z.
// Absent --camera: nullopt.
Result<std::optional<v1::Camera>> camera_flags(const Flags& flags);
// --width, --height, --exposure, --tonemap, --view-mode, --quality: only those given are set.
Result<v1::ViewSettings> view_settings_flags(const Flags& flags);
const std::vector<std::string>& view_setting_flag_names();

}  // namespace ddgi::client
