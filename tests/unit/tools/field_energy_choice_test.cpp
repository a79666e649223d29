// The energy calibration's choice rule (tools/field_energy.h) on made-up calibrations: the
// cheapest candidate within the target, else the closest with ties to the cheaper, paths per
// pixel only where no field candidate meets the acceptance; a view the path tracer finds black
// keeps the static default. The calibration itself on a GPU:
// tests/gpu/field_energy_test.cpp.
#include <gtest/gtest.h>

#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "tools/field_energy.h"

namespace ddgi::test {
namespace {

using tools::CalibratedCandidate;
using tools::Calibration;

// A calibration whose candidates err as given: {full, indirect} mean/ref each.
Calibration made_up(const std::vector<std::pair<double, double>>& ratios) {
  Calibration c;
  for (size_t i = 0; i < ratios.size(); ++i) {
    CalibratedCandidate point;
    point.candidate.name = "candidate " + std::to_string(i);
    point.mean_ratio = ratios[i].first;
    point.indirect_ratio = ratios[i].second;
    c.candidates.push_back(point);
  }
  return c;
}

size_t chosen(const std::vector<std::pair<double, double>>& ratios) {
  auto index = tools::choose_energy(made_up(ratios));
  EXPECT_TRUE(index.ok()) << index.error().message;
  return index.ok() ? *index : 999;
}

TEST(FieldEnergyChoice, CheapestWithinTheTargetElseTheClosestTiesToTheCheaper) {
  // The error is the worse of the two views.
  EXPECT_NEAR(tools::energy_error(made_up({{1.01, 0.93}}).candidates[0]), 0.07, 1e-12);
  EXPECT_NEAR(tools::energy_error(made_up({{1.06, 0.99}}).candidates[0]), 0.06, 1e-12);
  // The static default (first) stays while it is within 3%, though another errs less.
  EXPECT_EQ(chosen({{1.02, 0.98}, {1.0, 1.0}}), 0u);
  // The first within 3% in cheapest-first order, not the closest.
  EXPECT_EQ(chosen({{1.06, 1.06}, {0.975, 0.98}, {1.0, 1.0}}), 1u);
  // None within 3%: the closest, unless a cheaper one is within 0.5% of it.
  EXPECT_EQ(chosen({{0.90, 0.85}, {0.93, 0.94}, {0.95, 0.96}, {0.96, 0.94}}), 2u);
  EXPECT_EQ(chosen({{0.90, 0.85}, {0.953, 0.96}, {0.955, 0.96}}), 1u);
  // A view the path tracer finds black (ratios 0): every candidate errs alike, the default stays.
  EXPECT_EQ(chosen({{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}}), 0u);
  EXPECT_FALSE(tools::choose_energy(Calibration{}).ok());
  // Paths per pixel (noisy) count only where no field candidate is within the acceptance's 5%:
  // then the closest of all, else they are passed over though closer.
  auto with_pixel_paths = [](const std::vector<std::pair<double, double>>& ratios) {
    Calibration c = made_up(ratios);
    c.candidates.back().candidate.assignments = {std::begin(tools::kPixelPathsCandidate),
                                                 std::end(tools::kPixelPathsCandidate)};
    auto index = tools::choose_energy(c);
    EXPECT_TRUE(index.ok()) << index.error().message;
    return index.ok() ? *index : 999;
  };
  EXPECT_EQ(with_pixel_paths({{0.60, 0.55}, {0.70, 0.65}, {0.97, 0.96}}), 2u);
  EXPECT_EQ(with_pixel_paths({{0.60, 0.55}, {0.70, 0.65}, {1.02, 0.99}}), 2u);
  EXPECT_EQ(with_pixel_paths({{0.94, 0.91}, {0.96, 0.955}, {1.0, 1.0}}), 1u);
  EXPECT_EQ(with_pixel_paths({{1.0, 1.0}, {0.96, 0.955}, {1.0, 1.0}}), 0u);
  EXPECT_TRUE(tools::traces_pixel_paths({"x", {"pixel_paths=4"}}));
  EXPECT_FALSE(tools::traces_pixel_paths({"x", {"pixel_paths=0", "probe_bounces=1"}}));
  EXPECT_TRUE(tools::sets_energy_params({"pixel_path_vertices=8"}));
  // Which assignments are the calibration's to make.
  EXPECT_TRUE(tools::sets_energy_params({"rays_per_probe=64", "probe_bounces=0"}));
  EXPECT_TRUE(tools::sets_energy_params({"irradiance_gamma=5"}));
  EXPECT_FALSE(tools::sets_energy_params({"rays_per_probe=64", "probe_bounces_max=1"}));
  EXPECT_FALSE(tools::sets_energy_params({}));
}

}  // namespace
}  // namespace ddgi::test
