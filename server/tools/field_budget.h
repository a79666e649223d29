// A session's configuration (issue 45, "one rule for accuracy and time"): for a loaded scene and
// a frame size, the field configuration of lowest error whose cost fits a budget of GPU
// milliseconds per frame (the rule itself: tools/field_choice.h). The choice comes from
// measurements on this GPU for this scene, never from a table: a calibration warms each candidate
// up over the scene's own GPU copy, times every pass of its frame (shadow field, irradiance field,
// frame) at the budget's frame size, and scores a smaller frame against a path-traced reference
// (FLIP and the mean light, each with its noise). The candidates come from scene analysis and
// cover everything a session may trade: rays per probe, the grid, emitter sampling (only where
// emissive surfaces are), how a probe ray's light is gathered (traced bounces, self-shadowing
// bias, the blend's encoding: what decides whether the field keeps a scene's light) and paths per
// pixel. The service calibrates in the background after a session starts (service/calibrator.h)
// and keeps the result per scene, device, driver, frame size and base parameters (BudgetCache,
// on disk by default).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "gi/gi_stack.h"
#include "scene/scene.h"
#include "vk/context.h"

namespace ddgi::tools {

// One configuration the budget may pick: field assignments ("name=value") over the session's
// own parameters.
struct BudgetCandidate {
  std::string name;
  std::vector<std::string> assignments;
};

// The configurations worth measuring for `scene` over `base`, each an assignment of some of
// these axes over the base (the base itself, "static default", first):
// - light gathering: a self-shadowing bias of 0.5, one traced bounce past each probe ray's hit,
//   the two together, one bounce blended linearly (what keeps or loses a scene's light:
//   docs/results/default-energy.md);
// - rays per probe: 32, 64, the base's, 256;
// - emitter light sampled or carried by the field, whichever the base does not do (one sample
//   as well where the base takes more), only where the scene has emissive surfaces; crossed
//   with the static and one-bounce gathering only;
// - half the probes per axis over the same extent (single grids), at 32 rays;
// - paths per pixel (kPixelPathsCandidates), which bring light no probe grid holds, at the
//   base's rays.
// An axis whose parameters the session set by hand (`fixed`: "name=value" assignments or bare
// names) keeps them: it is not varied.
std::vector<BudgetCandidate> budget_candidates(const Scene& scene,
                                               const IrradianceFieldParams& base,
                                               const std::vector<std::string>& fixed = {});

// The paths-per-pixel candidates: 1 and 4 paths of up to 32 vertices. cornell_nvpro's albedo-1
// slot needs long paths (lavapipe, 160x90: 0.55 of the light with the field at the pixel, 0.61
// with 2 vertices, 0.76 with 8, 0.96 with 32; docs/results/default-energy.md).
inline constexpr uint32_t kPixelPathCounts[] = {1, 4};
inline constexpr uint32_t kPixelPathVertices = 32;

// Field updates after which a field is scored as settled: the budget calibration's and
// ddgi-eval's default warm-up.
inline constexpr uint32_t kConvergedWarmupUpdates = 64;

// How a calibration measures. Every field: default, range, reason.
struct CalibrationOptions {
  // The frame the budget pays for, in pixels; [16, 16384] each. 1080p: the product's stream.
  uint32_t width = 1920;
  uint32_t height = 1080;
  // Samples per pixel of the reference at the scored size (the frame scaled down to at most 320
  // pixels wide: the field's light is low-frequency, and the reference costs the square less),
  // [1, 65536]. 256: under a second on the H200 for the repo's scenes; tests pass fewer.
  uint32_t reference_spp = 256;
  // Field updates before a candidate is timed and scored, [1, 4096]: converged as a session is,
  // and as ddgi-eval's --warmup default (the same constant). After 32 (+ 7 timed) updates the
  // ranking followed how fast a field converges rather than where it settles: on two_rooms_open
  // (lavapipe, 320x180) FLIP fell with rays, 0.175 at 32 rays to 0.133 at 256, while after 65
  // updates 256 rays scored worst (0.161 against 0.150-0.155), and the budget chose 256 rays where
  // 32 measured 10% better at 1080p on the H100.
  uint32_t warmup_updates = kConvergedWarmupUpdates;
  // Timed frames per candidate (one field update each; the median counts), [1, 1000].
  uint32_t timed_frames = 7;
  // A candidate whose first timed frame costs more than this (ms) is timed by that frame alone,
  // [1, 1e6]: it fits no real-time budget, and its frames hold the one queue every stream shares
  // (paths per pixel at 1080p: 65-150 ms each).
  double slow_frame_ms = 50.0;
  // Frames scored per candidate, each after one more field update, [2, 16]: their mean is the
  // candidate's error, their spread its noise (CalibratedCandidate::flip_noise).
  uint32_t scored_frames = 3;
  // What the progress log calls the calibration ("budget calibration 3/8 ...").
  const char* purpose = "budget";
  // A background calibration's hooks (service/calibrator.h): `progress` after each candidate
  // with (done, total); `cancelled` before each, true ending the calibration (CANCELLED).
  struct Hooks {
    std::function<void(size_t, size_t)> progress;
    std::function<bool()> cancelled;
  };
  Hooks hooks;
  // Tests only (lavapipe's times mean nothing): each candidate's cost in ms, by index; timing
  // is skipped. Empty: measure.
  std::vector<double> injected_ms;
};
Status validate(const CalibrationOptions& options);

struct CalibratedCandidate {
  BudgetCandidate candidate;
  // Medians over the timed frames (GPU timestamps), by timing group: every pass a frame runs.
  double shadow_ms = 0.0;
  double field_ms = 0.0;
  double frame_ms = 0.0;
  uint32_t timed_frames = 0;  // how many (1 for a candidate over slow_frame_ms)
  // Mean over the scored frames of the full image's FLIP against the reference, and its
  // standard error (sample deviation / sqrt(frames)).
  double flip = 0.0;
  double flip_noise = 0.0;
  // Mean luminance over the reference's, and its standard error: the frames' spread and the
  // reference's own noise (Calibration::reference_noise), added in quadrature.
  double mean_ratio = 0.0;
  double mean_ratio_noise = 0.0;
  double cost_ms() const { return shadow_ms + field_ms + frame_ms; }
};

struct Calibration {
  std::string device;
  uint32_t width = 0, height = 0;
  std::vector<CalibratedCandidate> candidates;
  double seconds = 0.0;          // wall time the calibration took
  double reference_mean = 0.0;   // the reference's mean luminance (0: a black view)
  double reference_noise = 0.0;  // its relative noise (ReferencePair::mean_noise)
};

// Measures every candidate over one GI stack of `base` on `scene` seen by `camera` (the session's
// default view), logging progress per candidate.
Result<Calibration> calibrate(vk::Context& context, const Scene& scene, const Camera& camera,
                              const GiStackOptions& base,
                              const std::vector<BudgetCandidate>& candidates,
                              const CalibrationOptions& options);

// A budget in milliseconds per frame: (0, 1e6]; a second per frame is past any real-time use,
// but a CI job asking for "the best you have" may say 1e6.
inline constexpr double kMaxBudgetMs = 1e6;
Status check_budget_ms(double budget_ms);

// Calibrations kept per key (scene content, device, frame size, base parameters, options):
// a scene loaded again, by any session, is not measured again. In memory, and with a directory
// also on disk (one JSON file per key, written whole then renamed), so a restarted server does
// not measure again either; an unreadable file is measured over and rewritten. Thread-safe.
// Implemented in budget_cache.cpp.
class BudgetCache {
 public:
  using Measure = std::function<Result<Calibration>()>;
  // Keeps calibrations in `dir` too (created if missing); empty: memory only.
  Status persist_in(const std::string& dir);
  // The kept calibration of `key` (memory, then disk), if any: no measuring.
  std::optional<Calibration> find(const std::string& key);
  // Keeps `calibration` under `key` (and writes its file).
  void put(const std::string& key, const Calibration& calibration);
  // The cached calibration of `key`, or `measure`'s (kept when it succeeded); `from_cache` says
  // which.
  Result<Calibration> get_or_measure(const std::string& key, const Measure& measure,
                                     bool& from_cache);
  // The file a key is kept in (under the directory given to persist_in()).
  std::string file_of(const std::string& key) const;

 private:
  std::optional<Calibration> read_file(const std::string& key) const;
  void write_file(const std::string& key, const Calibration& calibration) const;

  std::mutex mutex_;
  std::map<std::string, Calibration> entries_;
  std::string dir_;
};

// What a calibration file's key starts with: a calibration measured by an older rule (other
// candidates, other fields) is never taken for one of this.
inline constexpr const char* kCalibrationFormat = "calibration v2";

// The cache key of a calibration: a hash of what decides its result (the scene's content, the
// device and driver, the frame, the options, the base parameters and what the session fixed).
std::string calibration_key(const vk::Context& context, const Scene& scene,
                            const GiStackOptions& base, const CalibrationOptions& options,
                            const std::vector<std::string>& fixed = {});

}  // namespace ddgi::tools
