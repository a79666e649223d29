#include "cli.h"

#include <google/protobuf/util/json_util.h>

#include <cstdio>
#include <iostream>

namespace ddgi::client {
namespace {

std::string json_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof(escaped), "\\u%04x", c);
          out += escaped;
        } else {
          out += c;
        }
    }
  }
  return out;
}

int print_error(const char* code, const std::string& message, int exit_code) {
  std::printf("{\"error\": {\"code\": \"%s\", \"message\": \"%s\"}}\n", code,
              json_escape(message).c_str());
  std::fprintf(stderr, "ddgi-client: %s: %s\n", code, message.c_str());
  return exit_code;
}

}  // namespace

std::unique_ptr<grpc::ClientContext> Cli::context(bool deadline) const {
  auto context = std::make_unique<grpc::ClientContext>();
  prepare(*context, connection, deadline);
  return context;
}

std::string to_json(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  std::string out;
  (void)google::protobuf::util::MessageToJsonString(message, &out, options);
  return out;
}

void print_json(const google::protobuf::Message& message) {
  std::fputs(to_json(message).c_str(), stdout);
  if (std::fflush(stdout) != 0) std::perror("ddgi-client: stdout");
}

int report(const grpc::Status& status) {
  return print_error(status_code_name(status.error_code()), status.error_message(), kExitRpcError);
}

int report(const Error& error) {
  return print_error(error_code_name(error.code), error.message,
                     error.code == ErrorCode::kInvalidArgument ? kExitUsage : kExitRpcError);
}

Result<std::string> session_flag(const Flags& flags) {
  DDGI_ASSIGN_OR_RETURN(const std::string session, flags.get_string("session", ""));
  if (session.empty()) return invalid_argument("--session ID is required (see `load`)");
  return session;
}

Result<v1::Vec3> vec3_flag(const Flags& flags, const std::string& name) {
  DDGI_ASSIGN_OR_RETURN(const std::vector<double> v, flags.get_doubles(name, 3, 3));
  v1::Vec3 out;
  out.set_x(float(v[0]));
  out.set_y(float(v[1]));
  out.set_z(float(v[2]));
  return out;
}

Result<std::optional<v1::Camera>> camera_flags(const Flags& flags) {
  if (!flags.has("camera")) {
    if (flags.has("up")) return invalid_argument("--up needs --camera");
    return std::optional<v1::Camera>();
  }
  DDGI_ASSIGN_OR_RETURN(const std::vector<double> v, flags.get_doubles("camera", 6, 7));
  v1::Camera camera;
  camera.mutable_position()->set_x(float(v[0]));
  camera.mutable_position()->set_y(float(v[1]));
  camera.mutable_position()->set_z(float(v[2]));
  camera.mutable_target()->set_x(float(v[3]));
  camera.mutable_target()->set_y(float(v[4]));
  camera.mutable_target()->set_z(float(v[5]));
  if (v.size() == 7) camera.set_vertical_fov_degrees(float(v[6]));
  if (flags.has("up")) {
    DDGI_ASSIGN_OR_RETURN(*camera.mutable_up(), vec3_flag(flags, "up"));
  }
  return std::optional<v1::Camera>(camera);
}

const std::vector<std::string>& view_setting_flag_names() {
  static const std::vector<std::string> names = {"width",     "height",  "exposure", "tonemap",
                                                 "view-mode", "quality", "camera",   "up"};
  return names;
}

Result<v1::ViewSettings> view_settings_flags(const Flags& flags) {
  v1::ViewSettings settings;
  // The server checks the ranges against its own limits; here only the types.
  if (flags.has("width")) {
    DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 0, 0, 1 << 30));
    settings.set_width(uint32_t(width));
  }
  if (flags.has("height")) {
    DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 0, 0, 1 << 30));
    settings.set_height(uint32_t(height));
  }
  if (flags.has("exposure")) {
    DDGI_ASSIGN_OR_RETURN(const double exposure, flags.get_double("exposure", 1.0, -1e30, 1e30));
    settings.set_exposure(float(exposure));
  }
  if (flags.has("quality")) {
    DDGI_ASSIGN_OR_RETURN(const int64_t quality, flags.get_int("quality", 0, 0, 1000));
    settings.set_jpeg_quality(uint32_t(quality));
  }
  if (flags.has("tonemap")) {
    DDGI_ASSIGN_OR_RETURN(const std::string text, flags.get_string("tonemap", ""));
    if (text == "aces") {
      settings.set_tonemap(v1::TONEMAP_ACES);
    } else if (text == "reinhard") {
      settings.set_tonemap(v1::TONEMAP_REINHARD);
    } else if (text == "clamp") {
      settings.set_tonemap(v1::TONEMAP_CLAMP);
    } else {
      return invalid_argument("--tonemap must be aces, reinhard or clamp (got '" + text + "')");
    }
  }
  if (flags.has("view-mode")) {
    DDGI_ASSIGN_OR_RETURN(const std::string text, flags.get_string("view-mode", ""));
    static const std::pair<const char*, v1::ViewMode> kModes[] = {
        {"full", v1::VIEW_MODE_FULL},         {"direct", v1::VIEW_MODE_DIRECT},
        {"indirect", v1::VIEW_MODE_INDIRECT}, {"albedo", v1::VIEW_MODE_ALBEDO},
        {"normal", v1::VIEW_MODE_NORMAL},     {"probes", v1::VIEW_MODE_PROBES}};
    bool found = false;
    for (const auto& [name, mode] : kModes) {
      if (text == name) {
        settings.set_view_mode(mode);
        found = true;
      }
    }
    if (!found) {
      return invalid_argument(
          "--view-mode must be full, direct, indirect, albedo, normal or probes (got '" + text +
          "')");
    }
  }
  return settings;
}

}  // namespace ddgi::client
