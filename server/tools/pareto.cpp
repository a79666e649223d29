// The Pareto harness's front, equal-time baseline, JSON and plot (tools/pareto.h).
#include "tools/pareto.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <nlohmann/json.hpp>

namespace ddgi::tools {
namespace {

using nlohmann::json;

json scores_json(const ImageScores& s) {
  return {{"psnr", s.psnr}, {"ssim", s.ssim}, {"flip", s.flip}, {"mean_ratio", s.mean_ratio}};
}

json config_json(const ConfigPoint& c) {
  return {{"name", c.name},
          {"assignments", c.assignments},
          {"field_ms", c.field_ms},
          {"frame_ms", c.frame_ms},
          {"total_ms", c.total_ms()},
          {"field_mib", c.field_mib},
          {"full", scores_json(c.full)},
          {"indirect", scores_json(c.indirect)}};
}

// null where a figure was not measured.
json optional_json(std::optional<double> value) {
  return value ? json(*value) : json(nullptr);
}

constexpr size_t kPlotNamesEveryConfigUpTo = 8;

ScatterPlot trade_plot(const SceneTrade& trade, const std::vector<size_t>& front) {
  ScatterPlot plot;
  plot.title = trade.scene + ": error against GPU time (" + std::to_string(trade.width) + "x" +
               std::to_string(trade.height) + ", reference " + std::to_string(trade.reference_spp) +
               " spp)";
  plot.x_label = "GPU ms per frame (field update + frame; path tracing: one image)";
  plot.y_label = "mean FLIP against the reference (lower is better)";
  PlotSeries configs{"DDGI configurations", {}}, best{"Pareto front", {}, true};
  PlotSeries traced{"path tracing (spp)", {}, true};
  // Past a handful of configurations their names overlap into an unreadable block (the H200's
  // 16-candidate sweeps): then only the front's points are named; the JSON names them all.
  const bool name_all = trade.configs.size() <= kPlotNamesEveryConfigUpTo;
  for (const ConfigPoint& c : trade.configs) {
    configs.points.push_back({c.total_ms(), c.full.flip, name_all ? c.name : ""});
  }
  for (size_t i : front) {
    const ConfigPoint& c = trade.configs[i];
    best.points.push_back({c.total_ms(), c.full.flip, name_all ? "" : c.name});
  }
  for (const PathTracePoint& p : trade.path_tracing) {
    traced.points.push_back({p.ms, p.full.flip, p.label()});
  }
  plot.series = {configs, best, traced};
  return plot;
}

}  // namespace

std::string PathTracePoint::label() const {
  const uint32_t pixels = downscale * downscale;
  if (pixels == 1 || spp % pixels == 0) return std::to_string(spp / pixels);
  return std::to_string(spp) + "/" + std::to_string(pixels);
}

std::vector<size_t> pareto_front(const std::vector<ConfigPoint>& configs) {
  std::vector<size_t> order(configs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double ta = configs[a].total_ms(), tb = configs[b].total_ms();
    return ta != tb ? ta < tb : configs[a].full.flip < configs[b].full.flip;
  });
  std::vector<size_t> front;
  double best_flip = INFINITY;
  for (size_t i : order) {
    if (configs[i].full.flip < best_flip) {
      front.push_back(i);
      best_flip = configs[i].full.flip;
    }
  }
  return front;
}

std::optional<double> best_flip_within(const std::vector<ConfigPoint>& configs, double ms) {
  std::optional<double> best;
  for (const ConfigPoint& c : configs) {
    if (c.total_ms() <= ms && (!best || c.full.flip < *best)) best = c.full.flip;
  }
  return best;
}

std::vector<EqualTimePoint> equal_time_points(const SceneTrade& trade) {
  std::vector<EqualTimePoint> points;
  for (double ms : kEqualTimeReportMs) {
    EqualTimePoint p{ms, best_flip_within(trade.configs, ms),
                     path_trace_flip_at(trade.path_tracing, ms), std::nullopt};
    p.flip_over_path_trace = ratio_of(p.best_flip_within, p.path_trace_flip);
    points.push_back(p);
  }
  return points;
}

std::optional<double> ratio_of(std::optional<double> a, std::optional<double> b) {
  return a && b && *b > 0.0 ? std::optional<double>(*a / *b) : std::nullopt;
}

std::optional<double> path_trace_flip_at(const std::vector<PathTracePoint>& points, double ms) {
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const PathTracePoint &a = points[i], &b = points[i + 1];
    if (!(a.ms > 0.0 && b.ms > a.ms) || ms < a.ms || ms > b.ms) continue;
    const double t = std::log(ms / a.ms) / std::log(b.ms / a.ms);
    return a.full.flip + t * (b.full.flip - a.full.flip);
  }
  if (points.size() == 1 && points[0].ms == ms) return points[0].full.flip;
  return std::nullopt;
}

std::optional<double> path_trace_ms_for(const std::vector<PathTracePoint>& points, double flip) {
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const PathTracePoint &a = points[i], &b = points[i + 1];
    const double fa = a.full.flip, fb = b.full.flip;
    if (!(a.ms > 0.0 && b.ms > 0.0) || fa == fb || flip > std::max(fa, fb) ||
        flip < std::min(fa, fb)) {
      continue;
    }
    const double t = (flip - fa) / (fb - fa);
    return a.ms * std::pow(b.ms / a.ms, t);
  }
  return std::nullopt;
}

Status write_scene_trade(const SceneTrade& trade, const std::string& dir) {
  const std::vector<size_t> front = pareto_front(trade.configs);
  json doc = {{"scene", trade.scene},     {"width", trade.width},
              {"height", trade.height},   {"reference_spp", trade.reference_spp},
              {"configs", json::array()}, {"path_tracing", json::array()},
              {"front", json::array()}};
  for (const ConfigPoint& c : trade.configs) doc["configs"].push_back(config_json(c));
  for (const PathTracePoint& p : trade.path_tracing) {
    doc["path_tracing"].push_back({{"spp", p.spp},
                                   {"downscale", p.downscale},
                                   {"samples_per_pixel", p.samples_per_pixel()},
                                   {"ms", p.ms},
                                   {"full", scores_json(p.full)}});
  }
  for (size_t i : front) {
    const ConfigPoint& c = trade.configs[i];
    json entry = {
        {"config", i}, {"name", c.name}, {"total_ms", c.total_ms()}, {"flip", c.full.flip}};
    const std::optional<double> traced = path_trace_flip_at(trade.path_tracing, c.total_ms());
    // null where the path tracer was not measured at this time (outside its spp range).
    entry["path_trace_flip_same_ms"] = optional_json(traced);
    entry["flip_over_path_trace"] = optional_json(ratio_of(c.full.flip, traced));
    entry["path_trace_ms_same_flip"] =
        optional_json(path_trace_ms_for(trade.path_tracing, c.full.flip));
    doc["front"].push_back(entry);
  }
  doc["equal_time"] = json::array();
  for (const EqualTimePoint& p : equal_time_points(trade)) {
    doc["equal_time"].push_back({{"ms", p.ms},
                                 {"best_flip_within", optional_json(p.best_flip_within)},
                                 {"path_trace_flip", optional_json(p.path_trace_flip)},
                                 {"flip_over_path_trace", optional_json(p.flip_over_path_trace)}});
  }
  DDGI_TRY(write_text_file(dir + "/" + trade.scene + ".json", doc.dump(2) + "\n"));
  return write_scatter_plot(dir + "/" + trade.scene, trade_plot(trade, front));
}

}  // namespace ddgi::tools
