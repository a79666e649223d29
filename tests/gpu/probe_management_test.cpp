// Probe management (issue 6): relocation out of thin walls and floors, states (Off inside
// geometry, Sleeping far from it), waking by moving objects, and the ray budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "gi/irradiance_field.h"
#include "gi/probe_state.h"
#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"
#include "tests/gpu/two_rooms.h"

namespace ddgi::test {
namespace {

uint32_t state_of(const gpu::ProbeState& s) {
  return static_cast<uint32_t>(probe_state(s));
}

class ProbeManagementTest : public GpuTest {
 protected:
  std::unique_ptr<GpuScene> upload(const Scene& scene) {
    auto gpu = GpuScene::create(context(), scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    return gpu.ok() ? std::move(gpu).value() : nullptr;
  }
  std::unique_ptr<IrradianceField> field(GpuScene& scene, const IrradianceFieldParams& p) {
    auto f = IrradianceField::create(context(), scene, p, context().default_backend());
    EXPECT_TRUE(f.ok()) << f.error().message;
    return f.ok() ? std::move(f).value() : nullptr;
  }
};

// Light-leak measures of one grid in a two-room scene.
struct LeakMeasure {
  float beside_wall = 0.0f;  // mean luminance on the lit side of the shared wall
  float dark_ratio = 0.0f;   // dark room mean over lit room mean: the light leak
};

// A grid like two_room_grid() but moved so that probes lie where they do harm: probe plane i
// at x = origin_x + 0.5 i, layer j at y = origin_y + 0.5 j.
IrradianceFieldParams placed(float origin_x, float origin_y) {
  IrradianceFieldParams p = two_room_grid();
  p.origin.x = origin_x;
  p.origin.y = origin_y;
  p.fixed_rays = 32;
  return p;
}

// The same grid with relocation (5 passes) and classification.
IrradianceFieldParams managed(IrradianceFieldParams p) {
  p.relocation_iterations = 5;
  p.classification = true;
  return p;
}

void report(const char* name, const LeakMeasure& stuck, const LeakMeasure& relocated) {
  std::printf("%-24s beside the wall %.4f -> %.4f, dark/lit %.5f%% -> %.5f%%\n", name,
              stuck.beside_wall, relocated.beside_wall, 100 * stuck.dark_ratio,
              100 * relocated.dark_ratio);
}

class RelocationTest : public ProbeManagementTest {
 protected:
  // Loads scenes/<name>, with the lit-room points right next to the wall, where stuck probes
  // darken.
  void load(const char* name) {
    auto scene = load_scene(std::string(DDGI_SOURCE_DIR) + "/scenes/" + name);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    gpu_ = upload(*scene);
    ASSERT_TRUE(gpu_);
    for (float y : {0.3f, 1.0f, 2.5f}) {
      for (float z : {-1.5f, -0.9f, 0.9f, 1.5f}) {
        beside_wall_.push_back({{-0.0101f, y, z}, {-1, 0, 0}, {-1, 0, 0}});
      }
    }
  }
  // 16 updates at hysteresis 0.8, then the measures; `states`, when given, receives the
  // probes' offsets and states.
  LeakMeasure measure(const IrradianceFieldParams& p,
                      std::vector<gpu::ProbeState>* states = nullptr) {
    auto f = field(*gpu_, p);
    EXPECT_TRUE(f);
    if (!f) return {};
    EXPECT_TRUE(f->update(16, DirectMode::kTracedShadows).ok());
    auto lit = f->query(room_points(-1.0f));
    auto dark = f->query(room_points(+1.0f));
    auto wall = f->query(beside_wall_);
    EXPECT_TRUE(lit.ok() && dark.ok() && wall.ok());
    if (!lit.ok() || !dark.ok() || !wall.ok()) return {};
    if (states) {
      auto read = f->read_probe_states();
      EXPECT_TRUE(read.ok());
      if (read.ok()) *states = *read;
    }
    return {mean_luminance(*wall), mean_luminance(*dark) / mean_luminance(*lit)};
  }
  LeakMeasure measure_clean() {
    const LeakMeasure clean = measure(two_room_grid());
    std::printf("%-24s beside the wall %.4f, dark/lit %.5f%%\n", "clean grid", clean.beside_wall,
                100 * clean.dark_ratio);
    return clean;
  }
  // Every probe of the wall plane (i = 8) left the wall, every probe of the floor layer (j = 0)
  // rose above it.
  static void expect_out_of_wall_and_floor(const std::vector<gpu::ProbeState>& states) {
    ASSERT_FALSE(states.empty());
    for (uint32_t p = 0; p < states.size(); ++p) {
      const gpu::ProbeState& s = states[p];
      if (state_of(s) == gpu::kProbeOff) continue;
      if (p % 16 == 8) {
        EXPECT_GT(std::abs(s.offset.x), 0.01f) << "probe " << p << " is in the wall";
      }
      if (p / 16 % 6 == 0) {
        EXPECT_GT(s.offset.y, 0.01f) << "probe " << p << " is in the floor";
      }
    }
  }

 private:
  std::unique_ptr<GpuScene> gpu_;
  std::vector<IrradianceQuery> beside_wall_;
};

// The closed-door scene (a closed 2 cm wall, single-sided floors). Each grid is measured stuck
// (no management) and relocated, against a clean grid (probes at x = -0.35 and 0.15: none in
// the wall or the floor):
// - In the floor plane (y = 0): these probes see the void under the floor; they darken the lit
//   room (a shadow leak) and leak a little light into the dark room; relocated, both drop.
// - Hugging the lit face of the wall (4 cm in front of it): the dark room's cages trust them
//   through the wall, so light leaks; relocated (pushed 0.2 m out), the leak drops.
// - Inside the closed wall and in the floor at once: probes inside the wall see only back
//   faces, so (2021 paper, sec. 4.1) they carry no light and shortened distances and cannot
//   leak light; the floor probes darken the lit side. Relocation moves them all out: the lit
//   side recovers, and the relocated wall probes, 0.2 m in front of the wall, let a small leak
//   through (0.12%, under 1%). The plane-wall test below is the case where probes in a wall
//   do leak.
// docs/probe-management.md lists the measured values.
TEST_F(RelocationTest, MovesProbesOutOfAClosedWallAndTheFloor) {
  ASSERT_NO_FATAL_FAILURE(load("two_rooms_closed.gltf"));
  const LeakMeasure clean = measure_clean();

  const IrradianceFieldParams in_floor = placed(-3.85f, 0.0f);
  const LeakMeasure floor_stuck = measure(in_floor), floor_relocated = measure(managed(in_floor));
  report("in the floor", floor_stuck, floor_relocated);
  EXPECT_LT(floor_stuck.beside_wall, 0.95f * clean.beside_wall);         // 0.868 vs 0.962
  EXPECT_GT(floor_relocated.beside_wall, 0.98f * clean.beside_wall);     // 0.974
  EXPECT_LT(floor_relocated.dark_ratio, 0.5f * floor_stuck.dark_ratio);  // 0.0004% vs 0.0046%

  const IrradianceFieldParams hugging = placed(-4.05f, 0.25f);  // plane 8 at x = -0.05
  const LeakMeasure hug_stuck = measure(hugging), hug_relocated = measure(managed(hugging));
  report("hugging the wall", hug_stuck, hug_relocated);
  EXPECT_LT(hug_relocated.dark_ratio, 0.5f * hug_stuck.dark_ratio);  // 0.051% vs 0.178%

  const IrradianceFieldParams in_wall = placed(-4.0f, 0.0f);  // plane 8 at x = 0, the wall
  std::vector<gpu::ProbeState> states;
  const LeakMeasure wall_stuck = measure(in_wall),
                    wall_relocated = measure(managed(in_wall), &states);
  report("in the wall and floor", wall_stuck, wall_relocated);
  // The shadow leak: stuck probes darken the lit side; relocation removes most of the error.
  EXPECT_LT(wall_stuck.beside_wall, 0.95f * clean.beside_wall);  // 0.890
  EXPECT_LT(std::abs(wall_relocated.beside_wall - clean.beside_wall),
            0.5f * std::abs(wall_stuck.beside_wall - clean.beside_wall));  // 0.964
  EXPECT_LT(wall_stuck.dark_ratio, 0.01f);       // 0.00004%: probes in the wall carry no light
  EXPECT_LT(wall_relocated.dark_ratio, 0.003f);  // 0.12%
  expect_out_of_wall_and_floor(states);
}

// The plane-wall scene: the rooms split by one double-sided quad at x = 0, the thinnest wall
// there is (and how game art often models partitions). A probe in its plane sees both rooms
// with its blended rays, so it carries the lit room's light into the dark room's cages: the
// classic DDGI light leak. Relocated (the fixed rays see the wall at distance ~0, a front face
// both ways), it steps 0.2 m off the wall to one side, and the leak drops.
TEST_F(RelocationTest, MovesProbesOutOfAPlaneWallAndTheFloorAndTheLeakDrops) {
  ASSERT_NO_FATAL_FAILURE(load("two_rooms_plane_wall.gltf"));
  const LeakMeasure clean = measure_clean();

  const IrradianceFieldParams in_wall = placed(-4.0f, 0.25f);  // plane 8 at x = 0, the wall
  const LeakMeasure wall_stuck = measure(in_wall), wall_relocated = measure(managed(in_wall));
  report("in the wall", wall_stuck, wall_relocated);

  const IrradianceFieldParams in_both = placed(-4.0f, 0.0f);  // and layer 0 in the floor
  std::vector<gpu::ProbeState> states;
  const LeakMeasure both_stuck = measure(in_both),
                    both_relocated = measure(managed(in_both), &states);
  report("in the wall and floor", both_stuck, both_relocated);
  // Stuck, the leak is over the field issue's 1% light-leak criterion and far over a clean
  // grid's (0.006%); relocated, it drops more than 5x, to under 1%.
  EXPECT_GT(wall_stuck.dark_ratio, 0.01f);                             // 9.2%
  EXPECT_LT(wall_relocated.dark_ratio, 0.2f * wall_stuck.dark_ratio);  // 0.88%
  EXPECT_LT(wall_relocated.dark_ratio, 0.01f);
  EXPECT_GT(both_stuck.dark_ratio, 0.01f);                             // 7.5%
  EXPECT_LT(both_relocated.dark_ratio, 0.2f * both_stuck.dark_ratio);  // 0.83%
  EXPECT_LT(both_relocated.dark_ratio, 0.01f);
  // The lit side loses the shadow leak of the stuck probes too.
  EXPECT_LT(both_stuck.beside_wall, 0.9f * clean.beside_wall);       // 0.767 vs 0.963
  EXPECT_GT(both_relocated.beside_wall, 0.98f * clean.beside_wall);  // 0.970
  expect_out_of_wall_and_floor(states);
}

// A solid 4 m box and a line of probes from its middle out into empty space: probes inside
// it (too deep to relocate out) are Off, those within a cage diagonal of its faces Vigilant,
// those further away Sleeping.
TEST_F(ProbeManagementTest, ProbesInsideSolidsAreOffAndFarFromGeometrySleep) {
  Scene scene;
  const int white = add_material(scene, glm::vec3(0.5f));
  add_box(scene, glm::scale(glm::mat4(1.0f), glm::vec3(4.0f)), white);
  auto gpu = upload(scene);
  ASSERT_TRUE(gpu);
  IrradianceFieldParams p;
  p.origin = {-1.5f, 0.0f, 0.0f};
  p.spacing = {1.0f, 1.0f, 1.0f};
  p.counts = {12, 1, 1};  // x = -1.5 .. 9.5
  p.rays_per_probe = 16;
  auto f = field(*gpu, p);
  ASSERT_TRUE(f);
  const ProbeScheduler& s = f->scheduler();
  for (uint32_t i = 0; i < 12; ++i) {
    const float x = -1.5f + float(i);
    const uint32_t expected = x < 2.0f   ? gpu::kProbeOff        // inside the box
                              : x < 3.6f ? gpu::kProbeVigilant   // face within sqrt(3) m
                                         : gpu::kProbeSleeping;  // nothing within reach
    EXPECT_EQ(s.state(i), expected)
        << "probe at x = " << x << " is " << probe_state_name(s.state(i));
  }
  const ProbeStateCounts counts = f->probe_counts();
  EXPECT_EQ(counts.off, 4u);
  EXPECT_EQ(counts.active(), 2u);
  EXPECT_EQ(counts.sleeping, 6u);
}

// An object moved next to sleeping probes wakes them before any frame is shaded by them: the
// renderer calls prepare() before recording the frame's field update, woken probes go first
// under the ray budget, and their first update takes its value at once (no history). Without
// the move (the control) the same frames leave the probes asleep and the box's place unlit.
TEST_F(ProbeManagementTest, MovingObjectWakesSleepingProbesBeforeTheyShade) {
  Scene scene;
  const int white = add_material(scene, glm::vec3(0.8f));
  // A floor 0.5 m under the lowest probe layer keeps the two lower layers Vigilant (traced
  // before the move, so the budget has other probes to serve); the upper two sleep.
  add_quad(scene, {-20, -2, 20}, {20, -2, 20}, {20, -2, -20}, {-20, -2, -20}, white);
  const int mover = add_box(scene, glm::translate(glm::mat4(1.0f), {40.0f, 0.0f, 0.0f}), white);
  Light light;
  light.position = {0.0f, 3.0f, 0.0f};
  light.intensity = 10.0f;
  scene.lights.push_back(light);
  auto gpu = upload(scene);
  ASSERT_TRUE(gpu);
  IrradianceFieldParams p;
  p.origin = {-1.5f, -1.5f, -1.5f};
  p.spacing = {1.0f, 1.0f, 1.0f};
  p.counts = {4, 4, 4};
  p.rays_per_probe = 32;
  p.fixed_rays = 32;
  p.max_rays_per_update = 8 * p.rays_per_probe;  // 8 probes per update
  // The box moves to y in [0.5, 1.5], among the sleeping layers. A point on its +x face, facing
  // the lit floor: its cage (layers y = 0.5 and 1.5) is lit only by probes traced since the move.
  const IrradianceQuery side{{0.5001f, 1.0f, 0.0f}, {1, 0, 0}, {1, 0, 0}};

  for (bool moved : {false, true}) {
    auto f = field(*gpu, p);
    ASSERT_TRUE(f);
    const ProbeStateCounts before = f->probe_counts();
    ASSERT_EQ(before.vigilant, 32u);
    ASSERT_EQ(before.sleeping, 32u);
    auto renderer = Renderer::create(context(), *gpu, f.get(), context().default_backend());
    ASSERT_TRUE(renderer.ok()) << renderer.error().message;
    FrameSettings settings;
    settings.width = 8;
    settings.height = 8;
    auto render = [&] { return render_updated(**renderer, settings, f.get()).ok(); };
    ASSERT_TRUE(render());  // the round-robin is under way
    auto asleep = f->read_probe_states();
    ASSERT_TRUE(asleep.ok());

    const glm::mat4 to =
        glm::translate(glm::mat4(1.0f), moved ? glm::vec3(0, 1, 0) : glm::vec3(40, 0, 0));
    ASSERT_TRUE(gpu->set_instance_transform(mover, to).ok());
    ASSERT_TRUE(render());  // prepare() runs inside
    const uint32_t woken = static_cast<uint32_t>(f->probe_counts().active() - before.active());
    // Enough frames for every woken probe at 8 per update, and no more.
    for (uint32_t u = 1; u < (woken + 7) / 8; ++u) ASSERT_TRUE(render());
    auto states = f->read_probe_states();
    ASSERT_TRUE(states.ok());
    auto lit = f->query({side});
    ASSERT_TRUE(lit.ok());
    std::printf("%s: %u probes woken, box side %.4g\n", moved ? "moved" : "control", woken,
                (*lit)[0].x);
    if (!moved) {
      EXPECT_EQ(woken, 0u);
      EXPECT_EQ((*lit)[0].x, 0.0f);  // the probes around x = 0.5 sleep, never traced
      continue;
    }
    EXPECT_GE(woken, 8u);  // at least the upper cage around the box
    // Every woken probe (Sleeping before the move) was updated within ceil(woken / 8) frames,
    // ahead of the Vigilant probes whose turn it was.
    for (uint32_t probe = 0; probe < states->size(); ++probe) {
      if (state_of((*asleep)[probe]) != gpu::kProbeSleeping) continue;
      if (state_of((*states)[probe]) != gpu::kProbeAwake) continue;
      EXPECT_EQ((*states)[probe].flags & gpu::kProbeResetHistory, 0u)
          << "woken probe " << probe << " not updated yet";
    }
    EXPECT_GT((*lit)[0].x, 0.0f);
  }
}

// With a budget below what the active probes need, no update traces more probe rays than the
// budget, and every active probe is updated within ceil(active / per_update) updates.
TEST_F(ProbeManagementTest, BudgetCapsRaysAndReachesEveryActiveProbe) {
  auto gpu = upload(make_cornell_box());
  ASSERT_TRUE(gpu);
  IrradianceFieldParams p;
  p.origin = {-0.75f, 0.25f, -0.75f};
  p.spacing = {0.5f, 0.5f, 0.5f};
  p.counts = {4, 4, 4};
  p.rays_per_probe = 24;
  p.fixed_rays = 8;
  const uint64_t per_probe = p.rays_per_probe;             // updates do not trace the fixed rays
  p.max_rays_per_update = 10 * per_probe + per_probe / 2;  // 10.5 probes' worth: 10 per update
  auto f = field(*gpu, p);
  ASSERT_TRUE(f);
  const uint64_t active = f->probe_counts().active();
  ASSERT_GT(active, 10u);
  const uint64_t bound = (active + 9) / 10;
  for (uint64_t u = 0; u < bound; ++u) {
    ASSERT_TRUE(f->update(1, DirectMode::kTracedShadows).ok());
    EXPECT_LE(f->last_update_probe_rays(), p.max_rays_per_update);
    EXPECT_GT(f->last_update_probe_rays(), 0u);
  }
  // An updated probe's history flag is cleared by the update's last pass.
  auto states = f->read_probe_states();
  ASSERT_TRUE(states.ok());
  for (uint32_t probe : f->scheduler().active()) {
    EXPECT_EQ((*states)[probe].flags & gpu::kProbeResetHistory, 0u)
        << "active probe " << probe << " not updated within " << bound << " updates";
  }
}

}  // namespace
}  // namespace ddgi::test
