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
  window = std::clamp<size_t>(window, 1, std::max<size_t>(error.size(), 1));
  int64_t first = -1;
  for (int64_t f = int64_t(error.size()) - int64_t(window); f >= 0; --f) {
    double mean = 0.0;
    for (size_t i = 0; i < window; ++i) mean += error[size_t(f) + i] / double(window);
    if (mean > factor * target) break;
    first = f;
  }
  return first;
}

double ResponseCurve::ms_until(int64_t frames) const {
  double sum = 0.0;
  for (int64_t f = 0; f < std::min<int64_t>(frames, int64_t(ms.size())); ++f) sum += ms[size_t(f)];
  return sum;
}

Status write_response_files(const std::string& dir, const std::string& stem,
                            const std::vector<ResponseCurve>& curves) {
  ScatterPlot plot;
  plot.title = stem + ": error per frame after the change";
  plot.x_label = "frames after the change";
  plot.y_label = "relative L1 error against the reference";
  plot.log_x = false;
  std::ostringstream csv;
  csv << "frame";
  size_t frames = 0;
  for (const ResponseCurve& curve : curves) {
    csv << "," << csv_field(curve.name);
    frames = std::max(frames, curve.error.size());
    PlotSeries series{curve.name, {}};
    for (size_t f = 0; f < curve.error.size(); ++f) {
      series.points.push_back({double(f), curve.error[f], ""});
    }
    plot.series.push_back(std::move(series));
  }
  csv << "\n";
  for (size_t f = 0; f < frames; ++f) {
    csv << f;
    for (const ResponseCurve& curve : curves) {
      csv << ",";
      if (f < curve.error.size()) csv << curve.error[f];
    }
    csv << "\n";
  }
  DDGI_TRY(write_text_file(dir + "/" + stem + ".response.svg", scatter_plot_svg(plot)));
  return write_text_file(dir + "/" + stem + ".response.csv", csv.str());
}

}  // namespace ddgi::tools
