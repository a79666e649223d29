// Shared pieces of the command-line tools (tools/tool_support.h).
#include "tools/tool_support.h"

#include <algorithm>
#include <array>
#include <cstdio>

#include "core/log.h"
#include "render/frame_target.h"
#include "scene/gltf_loader.h"

namespace ddgi::tools {

int tool_main(const char* tool, Status (*run)(int, char**), int argc, char** argv) {
  const Status status = run(argc, argv);
  if (status.ok()) return 0;
  std::fprintf(stderr, "%s: %s\n", tool, status.error().message.c_str());
  return status.error().code == ErrorCode::kInvalidArgument ? 2 : 1;
}

Result<std::unique_ptr<vk::Context>> context_from_flags(const Flags& flags) {
  vk::ContextOptions options;
  options.validation = flags.has("validation");
  DDGI_ASSIGN_OR_RETURN(options.device_filter, flags.get_string("device", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string backend, flags.get_string("backend", "auto"));
  DDGI_ASSIGN_OR_RETURN(options.backend, vk::parse_backend(backend));
  return vk::Context::create(options);
}

Result<Scene> load_scene_logged(const std::string& path) {
  DDGI_ASSIGN_OR_RETURN(Scene scene, load_scene(path));
  for (const std::string& warning : scene.warnings) LOG_WARNING << path << ": " << warning;
  return scene;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

std::string file_stem(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  return name.substr(0, name.find('.'));
}

void PassTable::add(const std::vector<vk::PassTime>& frame) {
  frames_.push_back(frame);
}

std::vector<PassTable::Row> PassTable::rows() const {
  std::vector<Row> rows;
  if (frames_.empty()) return rows;
  // Names repeat when a frame records several updates; each position is its own row.
  for (size_t p = 0; p < frames_.back().size(); ++p) {
    std::vector<double> ms;
    for (const auto& frame : frames_) {
      if (p < frame.size()) ms.push_back(frame[p].milliseconds);
    }
    rows.push_back({frames_.back()[p].name, frames_.back()[p].group, median(ms)});
  }
  return rows;
}

double PassTable::pass_median(const std::string& name) const {
  std::vector<double> ms;
  for (const auto& frame : frames_) {
    double sum = 0.0;
    for (const vk::PassTime& t : frame) {
      if (t.name == name) sum += t.milliseconds;
    }
    ms.push_back(sum);
  }
  return median(ms);
}

double PassTable::group_median(vk::PassGroup group) const {
  std::vector<double> ms;
  for (const auto& frame : frames_) ms.push_back(vk::group_milliseconds(frame, group));
  return median(ms);
}

double PassTable::others_median(vk::PassGroup group) const {
  std::vector<double> ms;
  for (const auto& frame : frames_) {
    double sum = 0.0;
    for (const vk::PassTime& t : frame) {
      if (t.group != group && t.group != vk::PassGroup::kBaseline) sum += t.milliseconds;
    }
    ms.push_back(sum);
  }
  return median(ms);
}

Status render_pipelined(vk::Context& context, Renderer& renderer, FrameSettings settings,
                        uint32_t frames, const FrameUpdates& updates, PassTable* table) {
  settings.read_radiance = false;
  std::array<std::unique_ptr<FrameTarget>, 2> targets;
  for (auto& target : targets) {
    DDGI_ASSIGN_OR_RETURN(target, FrameTarget::create(context, settings.width, settings.height));
  }
  std::array<PendingFrame, 2> pending;
  auto finish = [&](PendingFrame& frame) -> Status {
    if (!frame.active()) return ok_status();
    DDGI_ASSIGN_OR_RETURN(const FrameResult result, frame.finish());
    if (table) table->add(result.pass_times);
    return ok_status();
  };
  for (uint32_t f = 0; f < frames; ++f) {
    DDGI_TRY(finish(pending[f % 2]));  // the frame before last: its target is free again
    std::vector<vk::Pass> before;
    if (updates) {
      DDGI_ASSIGN_OR_RETURN(before, updates());
    }
    DDGI_ASSIGN_OR_RETURN(pending[f % 2], renderer.submit(settings, *targets[f % 2], before));
  }
  DDGI_TRY(finish(pending[frames % 2]));  // the older of the two left, first
  return finish(pending[(frames + 1) % 2]);
}

Status render_for(vk::Context& context, Renderer& renderer, const FrameSettings& settings,
                  std::chrono::milliseconds duration) {
  constexpr uint32_t kFramesPerCheck = 8;
  const auto until = std::chrono::steady_clock::now() + duration;
  do {
    DDGI_TRY(render_pipelined(context, renderer, settings, kFramesPerCheck, {}, nullptr));
  } while (std::chrono::steady_clock::now() < until);
  return ok_status();
}

}  // namespace ddgi::tools
