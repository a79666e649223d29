// Shared pieces of the command-line tools (tools/tool_support.h).
#include "tools/tool_support.h"

#include <algorithm>
#include <cstdio>

#include "core/log.h"
#include "scene/gltf_loader.h"

namespace ddgi::tools {

int tool_main(const char* tool, Status (*run)(int, char**), int argc, char** argv) {
  const Status status = run(argc, argv);
  if (status.ok()) return 0;
  std::fprintf(stderr, "%s: %s\n", tool, status.error().message.c_str());
  return status.error().code == ErrorCode::kInvalidArgument ? 2 : 1;
}

Result<std::unique_ptr<vk::Context>> context_from_flags(const Flags& flags,
                                                        vk::ContextOptions options) {
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

Status keep_gpu_busy(std::chrono::milliseconds duration, const std::function<Status()>& work) {
  const auto until = std::chrono::steady_clock::now() + duration;
  do {
    DDGI_TRY(work());
  } while (std::chrono::steady_clock::now() < until);
  return ok_status();
}

Status render_for(Renderer& renderer, const FrameSettings& settings,
                  std::chrono::milliseconds duration) {
  return keep_gpu_busy(duration, [&]() -> Status {
    DDGI_TRY(renderer.render(settings));
    return ok_status();
  });
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

}  // namespace ddgi::tools
