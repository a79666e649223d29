#version 460
#extension GL_GOOGLE_include_directive : require
// Irradiance of the field at given points and normals (scripted checks, tests, the RPC).
#include "common/field.glsl"
#include "common/dispatch.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { FieldDispatch pc; };

struct IrradianceQuery {
  vec3 position;
  float pad0;
  vec3 normal;     // unit
  float pad1;
  vec3 to_viewer;  // unit; the self-shadow bias leans this way
  float pad2;
};
layout(set = 1, binding = 0, scalar) readonly buffer Queries { IrradianceQuery queries[]; };
layout(set = 1, binding = 1, scalar) writeonly buffer Answers { vec4 answers[]; };

void main() {
  const uint id = linear_invocation(pc.row_width);
  if (id >= pc.count) return;
  const IrradianceQuery q = queries[id];
  answers[id] = vec4(sample_irradiance(q.position, q.normal, q.to_viewer), 0.0);
}
