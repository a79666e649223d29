// The speed-for-accuracy trade of one scene, as `ddgi-eval --pareto DIR` records it: every
// field configuration's GPU cost and error against the path-traced reference, the Pareto front
// over them, and the path tracer itself at 1/16, 1/4 (fewer pixels, upscaled), 1, 2, 4, ...
// samples per pixel as the equal-time baseline (issue 14). Written per scene as JSON
// (DIR/SCENE.json) and as a plot of FLIP against milliseconds (DIR/SCENE.svg and .png).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "tools/scatter_plot.h"

namespace ddgi::tools {

// Errors of one image against its reference (tone-mapped, one exposure per scene).
struct ImageScores {
  double psnr = 0.0;
  double ssim = 0.0;
  double flip = 0.0;        // mean FLIP: the axis of the front
  double mean_ratio = 0.0;  // mean linear luminance over the reference's
};

struct ConfigPoint {
  std::string name;
  std::vector<std::string> assignments;  // what was set, "name=value" (Config::all_assignments)
  double field_ms = 0.0;                 // medians over the timed frames
  double frame_ms = 0.0;
  double field_mib = 0.0;  // the field's GPU memory
  ImageScores full;
  ImageScores indirect;
  double total_ms() const { return field_ms + frame_ms; }
};

struct PathTracePoint {
  uint32_t spp = 0;        // per traced pixel
  uint32_t downscale = 1;  // traced at 1/downscale of the frame's width and height, upscaled
  double ms = 0.0;         // one image, GPU time of the tracing (the upscale not counted)
  ImageScores full;
  // Samples per frame pixel: 1/16 for one sample at a quarter of the size each way.
  double samples_per_pixel() const { return double(spp) / (double(downscale) * downscale); }
  std::string label() const;  // "1/16", "1/4", "1", "2", ...
};

struct SceneTrade {
  std::string scene;
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t reference_spp = 0;
  std::vector<ConfigPoint> configs;
  std::vector<PathTracePoint> path_tracing;  // ascending samples per pixel
};

// The configurations no other beats on both axes (lower total ms and lower FLIP), by ascending
// time: indices into `configs`.
std::vector<size_t> pareto_front(const std::vector<ConfigPoint>& configs);

// The lowest FLIP of a configuration whose total ms is at most `ms`; nothing when none fits.
std::optional<double> best_flip_within(const std::vector<ConfigPoint>& configs, double ms);

// The times at which the project reports DDGI's FLIP over the path tracer's (issue 14): the best
// configuration within each against the path tracer at exactly that time.
inline constexpr double kEqualTimeReportMs[] = {1.0, 2.0, 5.0};

// One of those times: each side's FLIP and their ratio, each nothing where it was not measured.
struct EqualTimePoint {
  double ms = 0.0;
  std::optional<double> best_flip_within;  // best_flip_within(configs, ms)
  std::optional<double> path_trace_flip;   // path_trace_flip_at(path_tracing, ms)
  std::optional<double> flip_over_path_trace;
};
std::vector<EqualTimePoint> equal_time_points(const SceneTrade& trade);

// a / b where both were measured and b > 0 (a FLIP over the path tracer's); else nothing.
std::optional<double> ratio_of(std::optional<double> a, std::optional<double> b);

// The path tracer's FLIP at `ms`, interpolated linearly in log(ms) between its measured points;
// nothing outside their range.
std::optional<double> path_trace_flip_at(const std::vector<PathTracePoint>& points, double ms);

// The path tracer's GPU ms to reach `flip`, interpolated linearly in log(ms) between the two
// measured points whose FLIPs bracket it; nothing when none do.
std::optional<double> path_trace_ms_for(const std::vector<PathTracePoint>& points, double flip);

// DIR/SCENE.json, DIR/SCENE.svg and DIR/SCENE.png (DIR must exist). The JSON holds every point, the
// front and, per front point, its FLIP over the path tracer's at the same time and the path
// tracer's ms for the same FLIP.
Status write_scene_trade(const SceneTrade& trade, const std::string& dir);

}  // namespace ddgi::tools
