#version 460
#extension GL_GOOGLE_include_directive : require
// Irradiance of the field at given points and normals (scripted checks, tests, the RPC).
#include "common/field.glsl"
#include "common/dispatch.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { FieldDispatch pc; };

layout(set = kFieldQuerySet, binding = kFieldQueryBindingQueries, scalar) readonly buffer Queries {
  FieldQuery queries[];
};
layout(set = kFieldQuerySet, binding = kFieldQueryBindingAnswers, scalar) writeonly buffer Answers {
  vec4 answers[];
};

void main() {
  const uint id = linear_invocation(pc.row_width);
  if (id >= pc.count) return;
  const FieldQuery q = queries[id];
  answers[id] = vec4(sample_irradiance(q.position, q.normal, q.to_viewer), 0.0);
}
