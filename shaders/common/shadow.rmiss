#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "common/ray_payloads.glsl"

layout(location = kPayloadShadow) rayPayloadInEXT ShadowPayload payload;

// Nothing blocked the ray: the transmittance gathered by any-hit stands.
void main() {}
