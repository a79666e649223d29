// A session's views (service/session_view.h).
#include "service/session_view.h"

#include "core/log.h"
#include "service/grpc_status.h"
#include "service/text.h"

namespace ddgi::service {

FrameSettings frame_settings(const ViewConfig& config, const Camera& camera,
                             DirectMode direct_mode) {
  FrameSettings settings;
  settings.width = config.width;
  settings.height = config.height;
  settings.camera = camera;
  settings.direct_mode = direct_mode;
  settings.view = config.view;
  settings.tonemap = config.tonemap;
  settings.exposure = config.exposure;
  // Views stream JPEG: only the 8-bit image is encoded, from the planes the GPU converted.
  settings.read_radiance = false;
  settings.read_yuv420 = true;
  return settings;
}

bool SessionView::wants_frame() const {
  if (!waiters.empty()) return true;
  for (const auto& stream : streams) {
    if (!stream->ended()) return true;
  }
  return false;
}

void SessionView::drop_ended_streams() {
  std::erase_if(streams, [](const auto& stream) { return stream->ended(); });
}

bool SessionView::resized() const {
  for (const auto& target : targets) {
    if (target && (target->width() != config.width || target->height() != config.height)) {
      return true;
    }
  }
  return false;
}

Result<std::shared_ptr<FrameTarget>> SessionView::take_target(vk::Context& context) {
  if (resized()) {
    for (auto& target : targets) target.reset();  // first, so the budget sees only new ones
  }
  std::shared_ptr<FrameTarget>& target = targets[next_target];
  if (!target) {
    DDGI_ASSIGN_OR_RETURN(std::unique_ptr<FrameTarget> made,
                          FrameTarget::create(context, config.width, config.height));
    target = std::move(made);
  }
  next_target ^= 1u;
  return target;
}

void SessionView::fail(const Error& error) {
  for (auto& stream : streams) stream->finish(to_grpc(error));
  for (auto& waiter : waiters) waiter(error);
  streams.clear();
  waiters.clear();
}

ViewSet::ViewSet(std::string session_id, uint32_t max_views, Metrics& metrics)
    : session_id_(std::move(session_id)), max_views_(max_views), metrics_(metrics) {}

Result<SessionView*> ViewSet::find(const std::string& view_id) {
  auto it = views_.find(view_id);
  if (it == views_.end()) {
    return not_found("session " + session_id_ + " has no view " + printable(view_id));
  }
  return &it->second;
}

Result<SessionView*> ViewSet::add(const ViewConfig& config, const Camera& camera, uint64_t seq) {
  if (views_.size() >= max_views_) {
    return resource_exhausted(
        "session " + session_id_ + " already has " + std::to_string(views_.size()) +
        " views, the most allowed (--max-views-per-session " + std::to_string(max_views_) + ")");
  }
  std::string id = "v";  // appended: GCC 12 at -O3 warns falsely (-Wrestrict) on "v" + string
  id.append(std::to_string(next_number_++));
  SessionView view;
  view.id = id;
  view.config = config;
  view.camera = camera;
  view.seq = seq;
  metrics_.views.fetch_add(1);
  return &views_.emplace(id, std::move(view)).first->second;
}

void ViewSet::erase(const std::string& view_id) {
  auto it = views_.find(view_id);
  if (it == views_.end()) return;
  SessionView& view = it->second;
  for (auto& stream : view.streams) stream->finish(grpc::Status::OK);
  for (auto& waiter : view.waiters) waiter(unavailable("view " + view_id + " was deleted"));
  metrics_.views.fetch_sub(1);
  views_.erase(it);
}

void ViewSet::detach(const std::shared_ptr<FrameStreamState>& stream) {
  std::vector<std::string> orphans;
  for (auto& [view_id, view] : views_) {
    const size_t before = view.streams.size();
    std::erase(view.streams, stream);
    if (view.streams.size() != before) {
      LOG_INFO << "stream detached session=" << session_id_ << " view=" << view_id
               << " dropped=" << stream->dropped();
    }
    // The frame loop may have dropped the ended stream already; either way a view made for a
    // stream goes with it.
    if (view.owned_by_stream && view.streams.empty()) orphans.push_back(view_id);
  }
  for (const std::string& view_id : orphans) erase(view_id);
}

void ViewSet::close_all(const Error& error, bool streams_fail) {
  const grpc::Status stream_end = streams_fail ? to_grpc(error) : grpc::Status::OK;
  for (auto& [view_id, view] : views_) {
    for (auto& stream : view.streams) stream->finish(stream_end);
    for (auto& waiter : view.waiters) waiter(error);
    metrics_.views.fetch_sub(1);
  }
  views_.clear();
}

uint32_t ViewSet::stream_count() const {
  uint32_t streams = 0;
  for (const auto& [id, view] : views_) streams += static_cast<uint32_t>(view.streams.size());
  return streams;
}

bool ViewSet::wants_frame() const {
  for (const auto& [id, view] : views_) {
    if (view.wants_frame()) return true;
  }
  return false;
}

}  // namespace ddgi::service
