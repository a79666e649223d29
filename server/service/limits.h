// What the service allows one client or all of them together: every quantity a request can
// make the server spend (sessions, pixels, bytes, points) has a cap, checked before the cost is
// paid. Set by ddgi-server's flags; reported by GetServerInfo.
#pragma once

#include <cstdint>

#include "core/result.h"

namespace ddgi::service {

struct ServiceLimits {
  // Default 8, range [1, 1024]: each session holds a scene, a field and a frame-loop thread.
  uint32_t max_sessions = 8;
  // Default 16, range [1, 256]: each view holds its own frame buffers.
  uint32_t max_views_per_session = 16;
  // Default 8, range [1, 256]: one-off frames (RenderFrame without a view id) of one session in
  // flight at once, from the call to its reply; each holds its settings, its image and its reply
  // until then. Calls beyond it are refused at once (RESOURCE_EXHAUSTED).
  uint32_t max_one_off_frames = 8;
  // Default 3840 x 2160 (4K UHD), range [1, 16384] each (the renderer's own limit).
  uint32_t max_width = 3840;
  uint32_t max_height = 2160;
  // Default 16 MiB, range [64 KiB, 1 GiB]: the largest message sent or received (uploads
  // aside). Must hold a JPEG frame at max_width x max_height; atlas dumps are chunked below it.
  uint64_t max_message_bytes = 16ull << 20;
  // Default 64 MiB, range [1 KiB, 1 GiB]: the largest uploaded .glb. The receive limit is raised
  // to fit one upload.
  uint64_t max_upload_bytes = 64ull << 20;
  // Default 65536, range [1, 1 M]: points in one QueryIrradiance.
  uint32_t max_query_points = 65536;
  // Default 256, range [1, 65536]: lights in one session (each adds a shadow ray per shaded
  // probe ray).
  uint32_t max_lights = 256;
  // Default 0 (the device's own size): GPU memory all sessions together may hold.
  uint64_t gpu_memory_budget_bytes = 0;
  // Default 60, range [1, 1000]: frames per second a session's loop renders at most.
  double max_fps = 60.0;
  // Default 1024, range [0, 65536]: field updates a session may run before its first frame.
  uint32_t max_warmup_updates = 1024;
};

// Errors name the limit (as its flag) and its range.
Status validate(const ServiceLimits& limits);

// The largest message the server accepts: big enough for one upload plus its request fields.
uint64_t max_receive_bytes(const ServiceLimits& limits);

}  // namespace ddgi::service
