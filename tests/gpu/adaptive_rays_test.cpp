// Adaptive rays (issue 14, item 5; docs/adaptive-rays.md) on the repo's two-room scene with the
// door closed: once the field has converged, only the maintenance slice is traced; moving the
// lit room's light heats the lit room's probes within one update and leaves the dark room's
// (which no light of that room reaches) settled; once caught up, the field's error against one
// converged on the moved light is within a stated tolerance of fixed rays', for fewer rays.
// Then what adaptive rays refuse, and ddgi-eval's record of the rays per frame around a change.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>
#include <sstream>
#include <string>

#include "gi/irradiance_field.h"
#include "gpu_scene/gpu_scene.h"
#include "scene/gltf_loader.h"
#include "tests/gpu/cli_run.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/two_rooms.h"

namespace ddgi::test {
namespace {

constexpr float kThreshold = 0.01f;  // settle_threshold of the adaptive fields
constexpr uint32_t kSettle = 48;     // updates to converge (warm_up(), then hysteresis 0.8)
constexpr DirectMode kDirect = DirectMode::kTracedShadows;
constexpr uint32_t kCountX = 16;  // two_room_grid's probes along x: x index < 8 is the lit room

class AdaptiveRaysTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    auto scene = load_scene(std::string(DDGI_SOURCE_DIR) + "/scenes/two_rooms_closed.gltf");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    auto gpu = GpuScene::create(context(), *scene);
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    gpu_ = std::move(*gpu);
  }

  std::unique_ptr<IrradianceField> field(float settle_threshold, uint32_t seed = 0) {
    IrradianceFieldParams p = two_room_grid();
    p.settle_threshold = settle_threshold;
    p.seed = seed;
    auto f = IrradianceField::create(context(), *gpu_, p, context().default_backend());
    EXPECT_TRUE(f.ok()) << f.error().message;
    return f.ok() ? std::move(*f) : nullptr;
  }

  // Hot probes per room.
  std::pair<int, int> hot_per_room(IrradianceField& f) {
    auto states = f.read_probe_states();
    EXPECT_TRUE(states.ok());
    if (!states.ok()) return {-1, -1};
    int lit = 0, dark = 0;
    for (size_t i = 0; i < states->size(); ++i) {
      if (((*states)[i].flags & gpu::kProbeHeatMask) == 0) continue;
      (i % kCountX < kCountX / 2 ? lit : dark) += 1;
    }
    return {lit, dark};
  }

  std::unique_ptr<GpuScene> gpu_;
};

// Mean encoded irradiance (largest channel) of each probe's map, in grid order.
std::vector<float> probe_means(IrradianceField& f) {
  auto atlas = f.read_irradiance_atlas();
  EXPECT_TRUE(atlas.ok());
  const uint32_t tile = f.params().irradiance_texels + 2;
  const uint32_t per_row = atlas->width / tile;
  const uint32_t probes = static_cast<uint32_t>(probe_count(f.params()));
  std::vector<float> means(probes, 0.0f);
  for (uint32_t p = 0; p < probes; ++p) {
    const uint32_t x0 = (p % per_row) * tile, y0 = (p / per_row) * tile;
    double sum = 0.0;
    for (uint32_t y = 1; y + 1 < tile; ++y) {
      for (uint32_t x = 1; x + 1 < tile; ++x) {
        const size_t i = (size_t(y0 + y) * atlas->width + x0 + x) * 4;
        sum += std::max({atlas->texels[i], atlas->texels[i + 1], atlas->texels[i + 2]});
      }
    }
    means[p] = float(sum / double((tile - 2) * (tile - 2)));
  }
  return means;
}

// Mean relative difference of the lit room's probe means from `reference`'s.
double lit_room_error(const std::vector<float>& means, const std::vector<float>& reference) {
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < means.size(); ++i) {
    if (i % kCountX >= kCountX / 2) continue;
    sum += std::abs(means[i] - reference[i]) / std::max(reference[i], 1e-6f);
    ++n;
  }
  return sum / n;
}

int count(const std::vector<uint8_t>& lit) {
  return std::accumulate(lit.begin(), lit.end(), 0);
}

// A converged field traces only its maintenance slice, and an update leaves every other probe's
// maps as they were (so the GPU skipped them, not just the count).
TEST_F(AdaptiveRaysTest, ConvergedFieldTracesOnlyItsMaintenanceSlice) {
  auto fixed = field(0.0f);
  auto adaptive = field(kThreshold);
  ASSERT_TRUE(fixed && adaptive);
  ASSERT_TRUE(fixed->warm_up(kSettle, kDirect).ok());
  ASSERT_TRUE(adaptive->warm_up(kSettle, kDirect).ok());
  auto fixed_lit = fixed->probes_lit_by_next_update();
  auto lit = adaptive->probes_lit_by_next_update();
  ASSERT_TRUE(fixed_lit.ok() && lit.ok());
  const int probes = static_cast<int>(lit->size());
  std::printf("after %u updates: fixed rays trace %d probes, adaptive %d of %d (slice %d)\n",
              kSettle, count(*fixed_lit), count(*lit), probes, probes / 8);
  EXPECT_EQ(count(*fixed_lit), probes);       // control: fixed rays trace every probe
  EXPECT_LE(count(*lit), probes * 15 / 100);  // measured 99 of 768: the slice and 3 hot
  EXPECT_GE(count(*lit), probes / 8);

  const std::vector<float> before = probe_means(*adaptive);
  ASSERT_TRUE(adaptive->update(1, kDirect).ok());
  const std::vector<float> after = probe_means(*adaptive);
  int lit_changed = 0, unlit_changed = 0;
  for (int i = 0; i < probes; ++i)
    ((*lit)[i] ? lit_changed : unlit_changed) += before[i] != after[i];
  std::printf("one update changed %d of the %d traced probes and %d of the others\n", lit_changed,
              count(*lit), unlit_changed);
  EXPECT_EQ(unlit_changed, 0);
  EXPECT_GE(lit_changed, count(*lit) * 9 / 10);  // traced probes do change (noise at least)
}

// Moving the lit room's light: every probe is traced in the next update (and the sweep's
// hot_updates), then the lit room's probes stay hot while the dark room's settle, and once the
// field has caught up its error against a converged field of the moved light is within a
// stated tolerance of fixed rays', for fewer rays.
TEST_F(AdaptiveRaysTest, MovedLightHeatsTheLitRoomAndTheFieldCatchesUp) {
  std::vector<Light> lights = gpu_->scene().lights;
  const glm::vec3 start = lights[0].position;
  lights[0].position = glm::vec3(-3.5f, 1.0f, 1.2f);  // a corner of the lit room, low
  ASSERT_TRUE(gpu_->set_lights(lights).ok());
  auto converged = field(0.0f, 7);
  ASSERT_TRUE(converged && converged->warm_up(2 * kSettle, kDirect).ok());
  const std::vector<float> target = probe_means(*converged);
  lights[0].position = start;
  ASSERT_TRUE(gpu_->set_lights(lights).ok());

  auto fixed = field(0.0f);
  auto adaptive = field(kThreshold);
  ASSERT_TRUE(fixed && adaptive);
  ASSERT_TRUE(fixed->warm_up(kSettle, kDirect).ok());
  ASSERT_TRUE(adaptive->warm_up(kSettle, kDirect).ok());
  const auto [lit_hot_before, dark_hot_before] = hot_per_room(*adaptive);
  const double stale_error = lit_room_error(probe_means(*adaptive), target);

  lights[0].position = glm::vec3(-3.5f, 1.0f, 1.2f);
  ASSERT_TRUE(gpu_->set_lights(lights).ok());
  auto first = adaptive->probes_lit_by_next_update();
  ASSERT_TRUE(first.ok());
  uint64_t adaptive_probes = 0;
  const uint32_t sweep = adaptive->params().hot_updates;
  std::pair<int, int> hot_after_sweep;
  for (uint32_t u = 0; u < kSettle; ++u) {
    auto lit = adaptive->probes_lit_by_next_update();
    ASSERT_TRUE(lit.ok());
    adaptive_probes += count(*lit);
    ASSERT_TRUE(fixed->update(1, kDirect).ok());
    ASSERT_TRUE(adaptive->update(1, kDirect).ok());
    if (u + 1 == sweep + 1) hot_after_sweep = hot_per_room(*adaptive);
  }
  const double fixed_error = lit_room_error(probe_means(*fixed), target);
  const double adaptive_error = lit_room_error(probe_means(*adaptive), target);
  const uint64_t fixed_probes = uint64_t(kSettle) * first->size();
  std::printf(
      "hot before the move: lit room %d, dark room %d; traced in the first update after "
      "it: %d of %zu; hot after the sweep: lit room %d, dark room %d\n",
      lit_hot_before, dark_hot_before, count(*first), first->size(), hot_after_sweep.first,
      hot_after_sweep.second);
  std::printf(
      "%u updates after the move: error fixed %.5f, adaptive %.5f (stale field %.5f); "
      "probes traced: adaptive %lu, fixed %lu (%.0f%%)\n",
      kSettle, fixed_error, adaptive_error, stale_error, adaptive_probes, fixed_probes,
      100.0 * double(adaptive_probes) / double(fixed_probes));
  const int room = static_cast<int>(first->size()) / 2;
  EXPECT_LE(lit_hot_before + dark_hot_before, room / 20);  // converged: measured 3
  EXPECT_EQ(count(*first), 2 * room);                      // within one update: every probe
  EXPECT_GE(hot_after_sweep.first, room * 3 / 4);          // measured 382 of 384
  EXPECT_LE(hot_after_sweep.second, room / 10);            // measured 14
  EXPECT_GT(stale_error, 10.0 * fixed_error);              // control: the move is a large change
  // Settled probes keep a gap below settle_threshold's drift, closed at the maintenance rate:
  // measured 0.00160 against fixed rays' 0.00096 (encoded probe means; ~0.3% of irradiance).
  EXPECT_LE(adaptive_error, fixed_error + 1.5e-3);
  EXPECT_LE(adaptive_probes, fixed_probes * 6 / 10);  // measured 43%
}

// What adaptive rays cannot measure is refused by name, and nothing changes.
TEST_F(AdaptiveRaysTest, RefusesWhatItCannotMeasure) {
  IrradianceFieldParams sh = two_room_grid();
  sh.basis = ProbeBasis::kSh;
  sh.settle_threshold = kThreshold;
  const Status refused = validate(sh);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("settle_threshold"), std::string::npos);
  EXPECT_NE(refused.error().message.find("basis=octahedral"), std::string::npos);

  auto adaptive = field(kThreshold);
  ASSERT_TRUE(adaptive);
  const Status split = adaptive->set_update_path(FieldUpdatePath::kSplit);
  ASSERT_FALSE(split.ok());
  EXPECT_NE(split.error().message.find("split update path"), std::string::npos);
  EXPECT_EQ(adaptive->update_path(), FieldUpdatePath::kFused);
  sh.basis = ProbeBasis::kOctahedral;  // control: the same parameters on octahedral probes
  EXPECT_TRUE(validate(sh).ok());
}

// ddgi-eval --dynamic records the rays each frame's update traced: on the Cornell box, a
// converged adaptive field traces a fraction of fixed rays' before the light moves, every probe
// in the frame after, and its rays plot is written.
TEST(AdaptiveRaysCli, EvalRecordsTheRaysOfEachFrameBeforeAndAfterTheChange) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ddgi-adaptive-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "out");
  const CliRun run = run_cli(DDGI_EVAL_EXE,
                             "scenes/cornell_box.gltf --width 32 --height 24 --spp 64 "
                             "--warmup 48 --response-static 6 --response-frames 10 "
                             "--dynamic light:0:-0.7,-0.3,0 --field counts=4,4,4 --configs "
                             "'fixed:;adaptive:settle_threshold=0.01' --pareto '" +
                                 (dir / "out").string() + "'",
                             dir);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  // Rows "frame,fixed,fixed rays,adaptive,adaptive rays,path tracing": frames -6 .. 9.
  std::istringstream csv(slurp(dir / "out" / "cornell_box.response.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("frame,fixed,fixed rays,adaptive,adaptive rays,", 0), 0u) << line;
  std::map<int, std::pair<double, double>> rays;  // frame: fixed, adaptive
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    std::string cell;
    while (std::getline(row, cell, ',')) cells.push_back(cell);
    ASSERT_GE(cells.size(), 5u) << line;
    rays[std::stoi(cells[0])] = {std::stod(cells[2]), std::stod(cells[4])};
  }
  ASSERT_EQ(rays.size(), 16u);
  ASSERT_EQ(rays.begin()->first, -6);
  const double all = 64.0 * IrradianceFieldParams{}.rays_per_probe;  // 4x4x4 probes
  std::printf(
      "rays per update before the change: fixed %.0f, adaptive %.0f; at the change: "
      "%.0f\n",
      rays[-1].first, rays[-1].second, rays[0].second);
  for (const auto& [frame, r] : rays) EXPECT_LE(r.second, r.first) << frame;
  EXPECT_LE(rays[-1].first, all);  // control: fixed rays trace every active probe
  EXPECT_GT(rays[-1].first, 0.5 * all);
  EXPECT_LE(rays[-1].second, 0.5 * rays[-1].first);  // converged: measured 1280 of 7168
  EXPECT_EQ(rays[0].second, rays[0].first);          // the change: every active probe
  const std::string svg = slurp(dir / "out" / "cornell_box.rays.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("probe rays per field update"), std::string::npos);
  EXPECT_GT(plot_pixels_of_colour(dir / "out" / "cornell_box.rays.png", 0x1f77b4), 45);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ddgi::test
