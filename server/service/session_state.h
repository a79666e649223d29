// The domain state of one session: its id and options, the scene it has loaded, its views and
// the one-off frames waiting for the next frame. Session runs its commands on it (on the loop
// thread); convert.cpp shows it on the wire (SessionInfo, SessionSummary).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "service/limits.h"
#include "service/metrics.h"
#include "service/one_off_frames.h"
#include "service/probe_stream.h"
#include "service/session_scene.h"
#include "service/session_view.h"

namespace ddgi::service {

struct SessionState {
  SessionState(std::string session_id, int64_t created, SessionOptions session_options,
               const ServiceLimits& limits, Metrics& metrics)
      : id(std::move(session_id)),
        created_unix_us(created),
        options(std::move(session_options)),
        views(id, limits.max_views_per_session, metrics) {}

  const std::string id;
  const int64_t created_unix_us;
  const SessionOptions options;
  std::unique_ptr<SessionScene> scene;  // null until the first load
  ViewSet views;
  OneOffFrames one_offs;
  std::vector<std::shared_ptr<ProbeStreamState>> probe_streams;  // StreamProbes calls
};

}  // namespace ddgi::service
