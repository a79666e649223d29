// Linear (one invocation per item) dispatches, folded into 2D when they are long: the host
// launches row_width x ceil(count / row_width) invocations (see vk::Kernel::dispatch_linear).
#ifndef DDGI_COMMON_DISPATCH_GLSL
#define DDGI_COMMON_DISPATCH_GLSL

#if defined(DDGI_BACKEND_PIPELINE)
uint linear_invocation(uint row_width) { return gl_LaunchIDEXT.x + gl_LaunchIDEXT.y * row_width; }
#else
uint linear_invocation(uint row_width) {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * row_width;
}
#endif

#endif
