#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "common/ray_payloads.glsl"

layout(location = kPayloadClosest) rayPayloadInEXT ClosestPayload payload;
hitAttributeEXT vec2 attributes;

void main() {
  payload.t = gl_HitTEXT;
  payload.instance = gl_InstanceCustomIndexEXT;
  payload.geometry = gl_GeometryIndexEXT;
  payload.primitive = gl_PrimitiveID;
  payload.barycentrics = attributes;
}
