// The dynamic-response measure of ddgi-eval --dynamic (tools/dynamic_response.h).
#include "tools/dynamic_response.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/flags.h"
#include "tools/scatter_plot.h"

namespace ddgi::tools {

Result<SceneChange> parse_scene_change(const std::string& text, const Scene& scene) {
  const std::string usage = "--dynamic takes light:INDEX:dx,dy,dz or object:INDEX:dx,dy,dz";
  const size_t first = text.find(':');
  const size_t second = first == std::string::npos ? first : text.find(':', first + 1);
  if (second == std::string::npos) return invalid_argument(usage + " (got '" + text + "')");
  SceneChange change;
  const std::string kind = text.substr(0, first);
  if (kind == "light") {
    change.kind = SceneChange::Kind::kLight;
  } else if (kind == "object") {
    change.kind = SceneChange::Kind::kObject;
  } else {
    return invalid_argument(usage + " (got kind '" + kind + "')");
  }
  DDGI_ASSIGN_OR_RETURN(const double index, parse_double(text.substr(first + 1, second - first - 1),
                                                         "--dynamic index"));
  const size_t count =
      change.kind == SceneChange::Kind::kLight ? scene.lights.size() : scene.instances.size();
  if (!(index >= 0.0 && index < double(count)) || index != std::floor(index)) {
    const std::string things = kind == "light"
                                   ? (count == 1 ? "light" : "lights")
                                   : (count == 1 ? "object instance" : "object instances");
    return invalid_argument("--dynamic: the scene has " + std::to_string(count) + " " + things +
                            "; index " + text.substr(first + 1, second - first - 1) +
                            " is not one of them");
  }
  change.index = size_t(index);
  std::istringstream offsets(text.substr(second + 1));
  std::string item;
  int axis = 0;
  while (std::getline(offsets, item, ',')) {
    if (axis == 3) return invalid_argument(usage + ": three offsets (got '" + text + "')");
    DDGI_ASSIGN_OR_RETURN(const double value, parse_double(item, "--dynamic offset"));
    if (!std::isfinite(value)) return invalid_argument("--dynamic: offsets must be finite");
    change.offset[axis++] = float(value);
  }
  if (axis != 3) return invalid_argument(usage + ": three offsets (got '" + text + "')");
  return change;
}

std::string describe(const Scene& scene, const SceneChange& change) {
  char text[256];
  const glm::vec3 extent = scene.world_bounds().extent();
  const bool light = change.kind == SceneChange::Kind::kLight;
  const std::string name =
      light ? scene.lights[change.index].name : scene.instances[change.index].name;
  std::snprintf(text, sizeof(text),
                "%s %zu '%s' moved by (%g, %g, %g); the scene spans (%.3g, %.3g, %.3g)",
                light ? "light" : "object", change.index, name.c_str(), change.offset.x,
                change.offset.y, change.offset.z, extent.x, extent.y, extent.z);
  return text;
}

Scene changed_scene(const Scene& scene, const SceneChange& change) {
  Scene out = scene;
  if (change.kind == SceneChange::Kind::kLight) {
    out.lights[change.index].position += change.offset;
  } else {
    out.instances[change.index].transform[3] += glm::vec4(change.offset, 0.0f);
  }
  return out;
}

double relative_l1(const std::vector<float>& test, const std::vector<float>& reference) {
  double difference = 0.0, total = 0.0;
  for (size_t i = 0; i < std::min(test.size(), reference.size()); ++i) {
    if (i % 4 == 3) continue;  // alpha
    difference += std::abs(double(test[i]) - double(reference[i]));
    total += std::abs(double(reference[i]));
  }
  return total > 0.0 ? difference / total : 0.0;
}

int64_t ResponseCurve::frames_until_within(double target, double factor, size_t window) const {
  const int64_t after = int64_t(error.size()) - change_frame;
  window = std::clamp<size_t>(window, 1, size_t(std::max<int64_t>(after, 1)));
  int64_t first = -1;
  for (int64_t f = after - int64_t(window); f >= 0; --f) {
    double mean = 0.0;
    for (size_t i = 0; i < window; ++i) {
      mean += error[size_t(change_frame + f) + i] / double(window);
    }
    if (mean > factor * target) break;
    first = f;
  }
  return first;
}

double ResponseCurve::ms_until(int64_t frames) const {
  double sum = 0.0;
  const int64_t end = std::min<int64_t>(change_frame + frames, int64_t(ms.size()));
  for (int64_t f = change_frame; f < end; ++f) sum += ms[size_t(f)];
  return sum;
}

namespace {

// One series per curve that has `values` (frame counted from the change on x).
ScatterPlot per_frame_plot(const std::vector<ResponseCurve>& curves,
                           std::vector<double> ResponseCurve::*values) {
  ScatterPlot plot;
  plot.x_label = "frames after the change";
  plot.log_x = false;
  for (const ResponseCurve& curve : curves) {
    if ((curve.*values).empty()) continue;
    PlotSeries series{curve.name, {}, true};
    for (size_t f = 0; f < (curve.*values).size(); ++f) {
      series.points.push_back({double(int64_t(f) - curve.change_frame), (curve.*values)[f], ""});
    }
    plot.series.push_back(std::move(series));
  }
  return plot;
}

}  // namespace

Status write_response_files(const std::string& dir, const std::string& stem,
                            const std::vector<ResponseCurve>& curves) {
  ScatterPlot errors = per_frame_plot(curves, &ResponseCurve::error);
  errors.title = stem + ": error per frame, the change at frame 0";
  errors.y_label = "relative L1 error against the reference";
  DDGI_TRY(write_scatter_plot(dir + "/" + stem + ".response", errors));
  ScatterPlot rays = per_frame_plot(curves, &ResponseCurve::rays);
  rays.title = stem + ": probe rays traced per frame, the change at frame 0";
  rays.y_label = "probe rays per field update";
  if (!rays.series.empty()) {
    DDGI_TRY(write_scatter_plot(dir + "/" + stem + ".rays", rays));
  }

  // Rows from the earliest frame before the change to the last after it.
  int64_t before = 0, after = 0;
  std::ostringstream csv;
  csv << "frame";
  for (const ResponseCurve& curve : curves) {
    csv << "," << csv_field(curve.name);
    if (!curve.rays.empty()) csv << "," << csv_field(curve.name + " rays");
    before = std::max(before, curve.change_frame);
    after = std::max(after, int64_t(curve.error.size()) - curve.change_frame);
  }
  csv << "\n";
  for (int64_t f = -before; f < after; ++f) {
    csv << f;
    for (const ResponseCurve& curve : curves) {
      const int64_t i = f + curve.change_frame;
      const bool has = i >= 0 && i < int64_t(curve.error.size());
      csv << ",";
      if (has) csv << curve.error[size_t(i)];
      if (curve.rays.empty()) continue;
      csv << ",";
      if (has && size_t(i) < curve.rays.size()) csv << curve.rays[size_t(i)];
    }
    csv << "\n";
  }
  return write_text_file(dir + "/" + stem + ".response.csv", csv.str());
}

}  // namespace ddgi::tools
