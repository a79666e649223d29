// What every command-line tool (ddgi-render, ddgi-bench, ddgi-eval, ddgi-shadow-eval) does the
// same way: the exit status of a run, the Vulkan context from the common flags, medians of
// timings, per-group totals of a frame's pass times, and untimed frames before timing.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/result.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "vk/context.h"
#include "vk/timer.h"

namespace ddgi::tools {

// Runs `run`; on failure prints "<tool>: <message>" to stderr. Exit status 0 on success, 2 for
// invalid arguments (usage errors), 1 for anything else.
int tool_main(const char* tool, Status (*run)(int, char**), int argc, char** argv);

// A context from --backend (auto | query | pipeline), --device and --validation, where the
// tool declared them, over `options` (the rest of what the tool wants).
Result<std::unique_ptr<vk::Context>> context_from_flags(const Flags& flags,
                                                        vk::ContextOptions options = {});

// Loads a scene, logging its warnings.
Result<Scene> load_scene_logged(const std::string& path);

double median(std::vector<double> values);

// How long untimed GPU work runs before timing, after CPU work (scoring an image) left the GPU
// idle. The driver sets the clock from the load: on the lent H100 (nvidia-smi every 200 ms,
// docs/results/budget/h200-2026-12-05.md) the SM clock rose from 345 to 1980 MHz over 0.8-1.2 s
// of load and fell back 1.4 s after the load stopped. Warmed for 0.5 s, six identical
// configurations timed 0.87-1.78 ms per frame; warmed for 3 s, 0.859-0.868 ms.
inline constexpr std::chrono::milliseconds kClockRampUp{2000};

// Calls `work` (untimed GPU work) until `duration` has passed, at least once.
Status keep_gpu_busy(std::chrono::milliseconds duration, const std::function<Status()>& work);

// Frames of `settings` without field updates (the field stays as it is) for `duration`, at
// least one: the GPU's clocks up again before timing, after CPU work left it idle.
Status render_for(Renderer& renderer, const FrameSettings& settings,
                  std::chrono::milliseconds duration);

// "dir/living_room.ddgi.json" -> "living_room": names of files written per scene.
std::string file_stem(const std::string& path);

// Median milliseconds over frames, per pass name (in first-seen order) and per pass group.
class PassTable {
 public:
  void add(const std::vector<vk::PassTime>& frame);
  struct Row {
    std::string name;
    vk::PassGroup group;
    double median_ms;
  };
  std::vector<Row> rows() const;
  double pass_median(const std::string& name) const;
  // The median over frames of each frame's summed time of `group`.
  double group_median(vk::PassGroup group) const;
  // The same for every group but `group` and the baselines (e.g. all frame-side passes).
  double others_median(vk::PassGroup group) const;

 private:
  std::vector<std::vector<vk::PassTime>> frames_;
};

}  // namespace ddgi::tools
