#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "common/ray_payloads.glsl"

layout(location = kPayloadShadow) rayPayloadInEXT ShadowPayload payload;

// An accepted hit on a shadow ray is an occluder.
void main() { payload.transmittance = vec3(0.0); }
