// ddgi-eval --path: see path_eval.h.
#include "tools/path_eval.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "gi/field_params.h"
#include "gpu_scene/camera_fit.h"
#include "render/renderer.h"
#include "scene/camera_path.h"
#include "tools/dynamic_response.h"
#include "tools/scatter_plot.h"
#include "tools/tool_support.h"

namespace ddgi::tools {
namespace {

// A scored view of the path: its time, camera and references.
struct PathView {
  std::string tag;   // in file names: STEM.TAG.reference.exr, STEM.TAG.CONFIG.exr
  int64_t step = 0;  // the frame that is scored
  double time = 0.0;
  Camera camera;
  ReferencePair refs;
};

// One configuration's walk.
struct PathWalk {
  std::string name;
  std::vector<ImageScores> full, indirect;  // per scored view
  std::vector<double> field_ms;             // per frame
  // Per frame from the second: the relative L1 change of the indirect view from the frame
  // before, and whether the field scrolled before drawing it.
  std::vector<double> change;
  std::vector<bool> scrolled;
  uint64_t probes = 0;
  double field_mib = 0.0;
};

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / double(v.size());
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

// Frames of the walk: one per 1/path_rate seconds from the path's start to its end.
int64_t path_frames(const EvalJob& job, const CameraPath& path) {
  return std::llround(std::floor(path.duration() * job.path_rate)) + 1;
}

// The views scored along the path (the frame nearest every job.path_every seconds) and their
// references, path-traced one after another with progress shown.
Result<std::vector<PathView>> path_views(vk::Context& context, const EvalJob& job,
                                         const Scene& scene, const CameraPath& path,
                                         const std::string& stem) {
  const float yfov = default_camera(scene).yfov;
  const int64_t frames = path_frames(job, path);
  std::vector<PathView> views;
  for (int64_t k = 0;; ++k) {
    PathView view;
    view.step = std::llround(double(k) * job.path_every * job.path_rate);
    if (view.step >= frames || (k > 0 && view.step == views.back().step)) break;
    view.time = double(view.step) / job.path_rate;
    view.camera = path.camera_at(view.time, yfov);
    views.push_back(view);
  }
  for (size_t k = 0; k < views.size(); ++k) {
    std::fprintf(stderr, "%s: reference %zu of %zu (t = %.1f s)\n", stem.c_str(), k + 1,
                 views.size(), views[k].time);
    char tag[32];
    std::snprintf(tag, sizeof(tag), "path%03zu", k);
    views[k].tag = stem + "." + tag;
    DDGI_ASSIGN_OR_RETURN(views[k].refs,
                          make_references(context, job, scene, views[k].camera, views[k].tag));
  }
  return views;
}

// One frame of the walk: a field update (the field following the camera first), the indirect
// view; at a scored view also the full frame, both scored.
struct Walker {
  GiStack& gi;
  Renderer& renderer;
  const EvalJob& job;
  PathWalk& walk;
  DirectMode direct_mode;       // the configuration's (Config::direct_mode)
  std::vector<float> previous;  // the last frame's indirect radiance

  Status frame(int64_t step, const Camera& camera, float exposure, const PathView* scored) {
    const bool scrolled = gi.field()->tracking_would_scroll(camera.position);
    gi.field()->track(camera.position);
    FrameSettings settings;
    settings.width = job.width;
    settings.height = job.height;
    settings.camera = camera;
    settings.exposure = exposure;
    settings.view = View::kIndirect;
    settings.direct_mode = direct_mode;
    DDGI_ASSIGN_OR_RETURN(const auto update, gi.frame_update(settings.direct_mode, {}));
    DDGI_ASSIGN_OR_RETURN(FrameResult indirect, renderer.render(settings, update));
    PassTable table;
    table.add(indirect.pass_times);
    walk.field_ms.push_back(table.group_median(vk::PassGroup::kIrradianceField));
    if (step > 0) {
      walk.change.push_back(relative_l1(indirect.radiance, previous));
      walk.scrolled.push_back(scrolled);
    }
    if (scored) {
      settings.view = View::kFull;
      DDGI_ASSIGN_OR_RETURN(const FrameResult full, renderer.render(settings));
      const ReferencePair& refs = scored->refs;
      DDGI_ASSIGN_OR_RETURN(const ImageScores f, score(refs.full.ldr, refs.full.radiance, full.ldr,
                                                       full.radiance, job.width, job.height));
      DDGI_ASSIGN_OR_RETURN(const ImageScores i,
                            score(refs.second.ldr, refs.second.radiance, indirect.ldr,
                                  indirect.radiance, job.width, job.height));
      walk.full.push_back(f);
      walk.indirect.push_back(i);
      std::string name = scored->tag + "." + walk.name;
      std::replace(name.begin(), name.end(), ' ', '-');
      DDGI_TRY(write_exr(job.out_dir, name, job.width, job.height, full.radiance));
      DDGI_TRY(
          write_exr(job.out_dir, name + "-indirect", job.width, job.height, indirect.radiance));
      std::printf("| %.1f | %.1f, %.1f, %.1f | %s | %.2f | %.4f | %.2f | %.4f |\n", scored->time,
                  camera.position.x, camera.position.y, camera.position.z, walk.name.c_str(),
                  f.psnr, f.flip, i.psnr, i.flip);
      std::fflush(stdout);
    }
    previous = std::move(indirect.radiance);
    return ok_status();
  }
};

// Walks `config` along the path: warmed up at the first view, then one frame per step.
Result<PathWalk> walk_config(vk::Context& context, const EvalJob& job, const Scene& scene,
                             const CameraPath& path, const std::vector<PathView>& views,
                             const Config& config) {
  PathWalk walk;
  walk.name = config.name;
  DDGI_ASSIGN_OR_RETURN(auto gi, make_gi_stack(context, job, scene, scene, config));
  DDGI_ASSIGN_OR_RETURN(auto renderer, make_renderer(context, *gi));
  gi->track(views.front().camera.position);
  DDGI_TRY(gi->warm_up(static_cast<uint32_t>(job.warmup)));
  walk.probes = probe_count(gi->field()->params());
  walk.field_mib = double(field_gpu_bytes(gi->field()->params())) / (1024.0 * 1024.0);
  Walker walker{*gi, *renderer, job, walk, config.direct_mode, {}};
  const int64_t steps = path_frames(job, path);
  const float yfov = views.front().camera.yfov;
  size_t next = 0;  // the next scored view
  for (int64_t step = 0; step < steps; ++step) {
    const bool scored = next < views.size() && views[next].step == step;
    // Frames use the exposure of the last scored view (only the LDR images depend on it; view 0
    // is frame 0, so there always is one).
    const float exposure = (scored ? views[next] : views[next - 1]).refs.exposure;
    const Camera camera = path.camera_at(double(step) / job.path_rate, yfov);
    DDGI_TRY(walker.frame(step, camera, exposure, scored ? &views[next] : nullptr));
    if (scored) ++next;
    if (step % 1000 == 999) {
      std::fprintf(stderr, "%s: frame %lld of %lld\n", config.name.c_str(),
                   static_cast<long long>(step + 1), static_cast<long long>(steps));
    }
  }
  return walk;
}

// A pop is a frame whose change stands out from its neighbours' (the camera's own motion changes
// every frame alike): the ratio of a frame's change to the larger of the frames' before and
// after it, for frames where the field scrolled and for all others.
struct SpikeRatios {
  std::vector<double> at_scroll, otherwise;
};

SpikeRatios spike_ratios(const PathWalk& w) {
  SpikeRatios r;
  for (size_t f = 1; f + 1 < w.change.size(); ++f) {
    const double around = std::max(w.change[f - 1], w.change[f + 1]);
    if (!(around > 0.0)) continue;
    (w.scrolled[f] ? r.at_scroll : r.otherwise).push_back(w.change[f] / around);
  }
  return r;
}

void print_summary(const std::vector<PathWalk>& walks) {
  std::printf(
      "\n| configuration | probes | field MiB | views | full: mean PSNR | mean FLIP | indirect: "
      "mean PSNR | mean FLIP | views with the lowest FLIP | field ms (median) | frames | scroll "
      "frames | change over neighbours' at scrolls: median / p99 / max | otherwise: median / p99 "
      "/ max |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const size_t views = walks.front().full.size();
  for (const PathWalk& w : walks) {
    std::vector<double> full_psnr, full_flip, indirect_psnr, indirect_flip;
    size_t lowest = 0;
    for (size_t v = 0; v < views; ++v) {
      full_psnr.push_back(w.full[v].psnr);
      full_flip.push_back(w.full[v].flip);
      indirect_psnr.push_back(w.indirect[v].psnr);
      indirect_flip.push_back(w.indirect[v].flip);
      bool best = true;
      for (const PathWalk& other : walks) best = best && w.full[v].flip <= other.full[v].flip;
      lowest += best;
    }
    const SpikeRatios spikes = spike_ratios(w);
    std::printf(
        "| %s | %llu | %.1f | %zu | %.2f | %.4f | %.2f | %.4f | %zu | %.3f | %zu | %zu | %.3f / "
        "%.3f / %.3f | %.3f / %.3f / %.3f |\n",
        w.name.c_str(), static_cast<unsigned long long>(w.probes), w.field_mib, views,
        mean(full_psnr), mean(full_flip), mean(indirect_psnr), mean(indirect_flip), lowest,
        median(w.field_ms), w.field_ms.size(), spikes.at_scroll.size(),
        quantile(spikes.at_scroll, 0.5), quantile(spikes.at_scroll, 0.99),
        quantile(spikes.at_scroll, 1.0), quantile(spikes.otherwise, 0.5),
        quantile(spikes.otherwise, 0.99), quantile(spikes.otherwise, 1.0));
  }
}

// DIR/STEM.path.svg, .png and .csv: full-frame FLIP at every scored view, per configuration.
Status write_path_files(const std::string& dir, const std::string& stem,
                        const std::vector<PathView>& views, const std::vector<PathWalk>& walks) {
  ScatterPlot plot;
  plot.title = stem + ": FLIP along the camera path";
  plot.x_label = "time on the path (s)";
  plot.y_label = "mean FLIP of the full frame against the path-traced reference";
  plot.log_x = false;
  std::ostringstream csv;
  csv << "time,x,y,z";
  for (const PathWalk& w : walks) {
    csv << "," << csv_field(w.name + " FLIP") << "," << csv_field(w.name + " PSNR");
    PlotSeries series{w.name, {}, true};
    for (size_t v = 0; v < views.size(); ++v) {
      series.points.push_back({views[v].time, w.full[v].flip, ""});
    }
    plot.series.push_back(std::move(series));
  }
  csv << "\n";
  for (size_t v = 0; v < views.size(); ++v) {
    const glm::vec3 p = views[v].camera.position;
    csv << views[v].time << "," << p.x << "," << p.y << "," << p.z;
    for (const PathWalk& w : walks) csv << "," << w.full[v].flip << "," << w.full[v].psnr;
    csv << "\n";
  }
  DDGI_TRY(write_scatter_plot(dir + "/" + stem + ".path", plot));
  return write_text_file(dir + "/" + stem + ".path.csv", csv.str());
}

}  // namespace

Status run_path(vk::Context& context, const EvalJob& job, const std::string& scene_path) {
  DDGI_ASSIGN_OR_RETURN(const CameraPath path, read_camera_path(job.camera_path));
  DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene_logged(scene_path));
  const std::string stem = file_stem(scene_path);
  std::printf("path %s: %.1f s, %zu keyframes; %.0f frames per second, scored every %.1f s\n\n",
              job.camera_path.c_str(), path.duration(), path.keyframes.size(), job.path_rate,
              job.path_every);
  DDGI_ASSIGN_OR_RETURN(const std::vector<PathView> views,
                        path_views(context, job, scene, path, stem));
  std::printf(
      "| t (s) | camera | configuration | full: PSNR | FLIP | indirect: PSNR | FLIP |\n"
      "|---|---|---|---|---|---|---|\n");
  std::vector<PathWalk> walks;
  for (const Config& config : job.configs) {
    DDGI_ASSIGN_OR_RETURN(PathWalk walk, walk_config(context, job, scene, path, views, config));
    walks.push_back(std::move(walk));
  }
  print_summary(walks);
  if (job.out_dir.empty()) return ok_status();
  return write_path_files(job.out_dir, stem, views, walks);
}

}  // namespace ddgi::tools
