// The views of a session: each is a client's camera and image settings, the two frame targets
// its frames alternate between (one can be drawn while the other's frame is still in flight),
// and who waits for its frames (streams, one-shot RenderFrame calls). A ViewSet
// holds a session's views by id and enforces --max-views-per-session. Owned and used by the
// session's loop thread only.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "render/frame_target.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "service/frame_encoder.h"
#include "service/frame_stream.h"
#include "service/metrics.h"
#include "vk/context.h"

namespace ddgi::service {

// How one view's frames look (everything but the camera).
struct ViewConfig {
  uint32_t width = 640;
  uint32_t height = 480;
  float exposure = 1.0f;
  Tonemap tonemap = Tonemap::kAces;
  View view = View::kFull;
  // 85: small frames for streaming with no visible blocking on renders.
  int jpeg_quality = 85;
};

// The renderer's settings for a frame of `config` seen by `camera` (8-bit image only: views
// stream JPEG).
FrameSettings frame_settings(const ViewConfig& config, const Camera& camera,
                             DirectMode direct_mode);

struct SessionView {
  std::string id;
  ViewConfig config;
  Camera camera;
  // Made when first drawn into, remade when resized. Shared with the frames in flight: a frame
  // holds its target until it is read back, whatever happens to the view meanwhile.
  std::array<std::shared_ptr<FrameTarget>, 2> targets;
  uint32_t next_target = 0;  // the target of the next frame
  std::vector<std::shared_ptr<FrameStreamState>> streams;
  std::vector<FrameWaiter> waiters;
  bool owned_by_stream = false;  // deleted when its stream ends
  uint64_t seq = 0;              // the command that last changed it

  // A live stream or a waiting RenderFrame.
  bool wants_frame() const;
  void drop_ended_streams();
  // Whether a target was made at another size than the config's now.
  bool resized() const;
  // The target of the next frame at the config's size, made or remade (after resized(), the
  // caller finishes the frames in flight first, so the budget sees only the new targets); the
  // frame after it goes to the other one.
  Result<std::shared_ptr<FrameTarget>> take_target(vk::Context& context);
  // Ends its streams with `error` and answers its waiters with it.
  void fail(const Error& error);
};

class ViewSet {
 public:
  ViewSet(std::string session_id, uint32_t max_views, Metrics& metrics);
  ViewSet(const ViewSet&) = delete;
  ViewSet& operator=(const ViewSet&) = delete;

  // NOT_FOUND naming the session and view.
  Result<SessionView*> find(const std::string& view_id);
  // A new view with the next id; RESOURCE_EXHAUSTED beyond --max-views-per-session.
  Result<SessionView*> add(const ViewConfig& config, const Camera& camera, uint64_t seq);
  // Ends its streams with OK and fails its waiters ("view v1 was deleted").
  void erase(const std::string& view_id);
  // Takes `stream` off every view; views made for it go with it.
  void detach(const std::shared_ptr<FrameStreamState>& stream);
  // Teardown: streams end with OK (with `error` when `streams_fail`), waiters get `error`,
  // every view goes.
  void close_all(const Error& error, bool streams_fail);

  std::map<std::string, SessionView>& all() { return views_; }
  const std::map<std::string, SessionView>& all() const { return views_; }
  size_t size() const { return views_.size(); }
  uint32_t stream_count() const;
  bool wants_frame() const;

 private:
  const std::string session_id_;
  const uint32_t max_views_;
  Metrics& metrics_;
  std::map<std::string, SessionView> views_;
  uint64_t next_number_ = 1;
};

}  // namespace ddgi::service
