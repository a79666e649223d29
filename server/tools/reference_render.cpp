// The tools' path-traced references (tools/reference_render.h).
#include "tools/reference_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/log.h"
#include "encode/write_image.h"
#include "tools/eval_job.h"

namespace ddgi {
namespace {

using Clock = std::chrono::steady_clock;

// Short GPU submissions keep progress lines flowing and stay clear of driver watchdogs.
constexpr double kBatchSeconds = 1.0;
constexpr double kProgressSeconds = 5.0;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Status write(const ReferenceOptions& options, const PathTraceImage& image) {
  DDGI_ASSIGN_OR_RETURN(const encode::ImageFormat format,
                        encode::format_from_path(options.out_path));
  if (format == encode::ImageFormat::kExr) {
    return encode::write_image(options.out_path,
                               encode::rgb_from_rgba(image.width, image.height, image.radiance));
  }
  encode::WriteOptions write_options;
  write_options.jpeg_quality = options.jpeg_quality;
  return encode::write_image(
      options.out_path, encode::ImageRgba8{image.width, image.height, image.ldr}, write_options);
}

}  // namespace

Status render_reference(vk::Context& context, GpuScene& scene, vk::TraceBackend backend,
                        const ReferenceOptions& options) {
  DDGI_TRY(validate(options.settings));
  DDGI_TRY(encode::format_from_path(options.out_path));  // fail before the long part
  DDGI_ASSIGN_OR_RETURN(auto tracer, PathTracer::create(context, scene, backend));
  LOG_INFO << "reference: " << options.samples << " samples per pixel, " << scene.emitter_count()
           << " emissive triangles, max bounces " << options.settings.max_bounces << ", seed "
           << options.settings.seed;

  const Clock::time_point start = Clock::now();
  Clock::time_point last_report = start;
  uint32_t batch = 1;
  while (tracer->samples() < options.samples) {
    batch = std::min(batch, options.samples - tracer->samples());
    const Clock::time_point batch_start = Clock::now();
    DDGI_TRY(tracer->accumulate(options.settings, batch));
    // Size the next batch to about kBatchSeconds from this one's time per sample.
    const double per_sample = std::max(seconds_since(batch_start), 1e-6) / batch;
    batch = static_cast<uint32_t>(std::clamp(kBatchSeconds / per_sample, 1.0, 65536.0));
    if (std::chrono::duration<double>(Clock::now() - last_report).count() >= kProgressSeconds) {
      last_report = Clock::now();
      const double elapsed = seconds_since(start);
      const double remaining = elapsed / tracer->samples() * (options.samples - tracer->samples());
      LOG_INFO << "reference: " << tracer->samples() << "/" << options.samples
               << " samples per pixel, " << std::lround(elapsed) << " s elapsed, about "
               << std::lround(remaining) << " s left";
    }
  }
  const double elapsed = seconds_since(start);
  DDGI_ASSIGN_OR_RETURN(const PathTraceImage image,
                        tracer->read(options.tonemap, options.exposure));
  DDGI_TRY(write(options, image));
  std::printf("%s: %ux%u, reference path tracer, %u samples per pixel, backend %s, device %s\n",
              options.out_path.c_str(), image.width, image.height, image.samples,
              vk::backend_name(backend), context.caps().device_name.c_str());
  std::printf("%.3f s, %.1f ms per sample of every pixel\n", elapsed,
              elapsed * 1e3 / image.samples);
  return context.no_validation_messages();
}

Result<ReferencePair> reference_pair(vk::Context& context, GpuScene& scene,
                                     const ReferencePairOptions& options) {
  ReferencePair pair;
  PathTraceSettings& pt = pair.settings;
  pt.width = options.width;
  pt.height = options.height;
  pt.camera = options.camera;
  pt.jitter = false;  // frames trace pixel centres too
  DDGI_ASSIGN_OR_RETURN(auto tracer, PathTracer::create(context, scene, context.default_backend()));
  auto accumulate = [&](PathTraceView view, uint32_t spp) -> Status {
    PathTraceSettings settings = pt;
    settings.view = view;
    for (uint32_t done = 0; done < spp;) {
      const uint32_t batch = std::min(64u, spp - done);
      DDGI_TRY(tracer->accumulate(settings, batch));
      done += batch;
    }
    return ok_status();
  };
  // The full reference first: it sets the exposure both are tone-mapped with. Read at half
  // its samples too where its noise is wanted: the second half's mean is 2 x full - first.
  const uint32_t first_half = options.estimate_mean_noise ? options.full_spp / 2 : 0;
  double first_half_mean = 0.0;
  if (first_half > 0) {
    DDGI_TRY(accumulate(PathTraceView::kFull, first_half));
    DDGI_ASSIGN_OR_RETURN(const PathTraceImage half, tracer->read(Tonemap::kAces, 1.0f));
    first_half_mean = tools::mean_luminance(half.radiance);
  }
  DDGI_TRY(accumulate(PathTraceView::kFull, options.full_spp - first_half));
  DDGI_ASSIGN_OR_RETURN(const PathTraceImage linear, tracer->read(Tonemap::kAces, 1.0f));
  if (first_half > 0) {
    const double full_mean = tools::mean_luminance(linear.radiance);
    const double second_half_mean = 2.0 * full_mean - first_half_mean;
    pair.mean_noise =
        full_mean > 0.0 ? std::abs(first_half_mean - second_half_mean) / (2.0 * full_mean) : 0.0;
  }
  pair.exposure = options.exposure ? options.exposure(linear.radiance) : 1.0f;
  DDGI_ASSIGN_OR_RETURN(pair.full, tracer->read(Tonemap::kAces, pair.exposure));
  if (options.second_spp == 0) return pair;
  DDGI_TRY(accumulate(options.second_view, options.second_spp));
  DDGI_ASSIGN_OR_RETURN(pair.second, tracer->read(Tonemap::kAces, pair.exposure));
  return pair;
}

Result<ReferencePair> reference_pair(vk::Context& context, const Scene& scene,
                                     const ReferencePairOptions& options) {
  DDGI_ASSIGN_OR_RETURN(auto gpu_scene, GpuScene::create(context, scene));
  return reference_pair(context, *gpu_scene, options);
}

}  // namespace ddgi
