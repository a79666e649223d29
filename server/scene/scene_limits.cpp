#include "scene/scene_limits.h"

#include <string>

namespace ddgi {
namespace {

Status check_range(const char* name, uint64_t value, uint64_t min, uint64_t max) {
  if (value < min || value > max) {
    return invalid_argument("SceneLimits::" + std::string(name) + " = " + std::to_string(value) +
                            " is outside [" + std::to_string(min) + ", " + std::to_string(max) +
                            "]");
  }
  return ok_status();
}

}  // namespace

Status validate_limits(const SceneLimits& limits) {
  DDGI_TRY(check_range("max_file_bytes", limits.max_file_bytes, 1024, (4ull << 30) - 1));
  DDGI_TRY(check_range("max_texture_dimension", limits.max_texture_dimension, 1, 32768));
  DDGI_TRY(check_range("max_total_texture_bytes", limits.max_total_texture_bytes, 0, 64ull << 30));
  DDGI_TRY(check_range("max_triangles", limits.max_triangles, 1, 1ull << 30));
  DDGI_TRY(check_range("max_vertices", limits.max_vertices, 1, 1ull << 30));
  DDGI_TRY(check_range("max_instances", limits.max_instances, 1, 1u << 24));
  DDGI_TRY(check_range("max_primitives", limits.max_primitives, 1, 1u << 24));
  DDGI_TRY(check_range("max_lights", limits.max_lights, 0, 1u << 20));
  DDGI_TRY(check_range("max_node_depth", limits.max_node_depth, 1, 65536));
  DDGI_TRY(check_range("max_json_depth", limits.max_json_depth, 8, 1024));
  DDGI_TRY(check_range("max_environment_width", limits.max_environment_width, 1, 65536));
  DDGI_TRY(check_range("max_environment_height", limits.max_environment_height, 1, 65536));
  return ok_status();
}

}  // namespace ddgi
