#version 460
#extension GL_GOOGLE_include_directive : require
// Irradiance of the field at given points and normals (scripted checks, tests, the RPC): the
// blend over the field's volumes, or one volume alone (pc.mode).
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
  if (pc.mode == kQueryBlended) {
    answers[id] = vec4(sample_irradiance(q.position, q.normal, q.to_viewer), 0.0);
  } else {
    field_volume = pc.mode - kQueryVolume0;
    answers[id] = vec4(sample_volume_irradiance(q.position, q.normal, q.to_viewer), 0.0);
  }
}
