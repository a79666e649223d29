// Lets one header describe GPU data for both C++ and GLSL.
// In C++ the types are GLM's inside namespace ddgi::gpu; in GLSL they are the built-ins.
#ifndef DDGI_SHARED_INTEROP_H
#define DDGI_SHARED_INTEROP_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>
#define DDGI_NAMESPACE_BEGIN namespace ddgi::gpu {
#define DDGI_NAMESPACE_END }
#define DDGI_CONST inline constexpr
namespace ddgi::gpu {
using uint = uint32_t;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec2 = glm::ivec2;
using ivec3 = glm::ivec3;
using uvec2 = glm::uvec2;
using uvec3 = glm::uvec3;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
}  // namespace ddgi::gpu
#else
#define DDGI_NAMESPACE_BEGIN
#define DDGI_NAMESPACE_END
#define DDGI_CONST const
#endif

#endif
