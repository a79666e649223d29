#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "common/ray_payloads.glsl"

layout(location = kPayloadClosest) rayPayloadInEXT ClosestPayload payload;

void main() { payload.t = -1.0; }
