// The ddgi-bench executable on a tiny configuration: its table has a row per update path with
// the raw-ray baselines (timed in the same submissions, kernels built only for the benchmark)
// and ratios that follow from the printed times; bad flags are refused by name.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/gpu/cli_run.h"

namespace ddgi::test {
namespace {

CliRun bench(const std::string& arguments) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("ddgi-bench-cli-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  CliRun run = run_cli(DDGI_BENCH_EXE, arguments, dir);
  std::filesystem::remove_all(dir);
  return run;
}

// The cells of the markdown table row that starts with `first_cell` and has `path` in it.
std::vector<std::string> row_cells(const std::string& out, const std::string& first_cell,
                                   const std::string& path) {
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    const std::vector<std::string> cells = markdown_cells(line);
    if (!cells.empty() && cells[0] == first_cell && cells.size() > 5 && cells[5] == path) {
      return cells;
    }
  }
  return {};
}

// The value in `column` of the Cornell box's row for `path`.
double cell(const std::string& out, const std::string& path, const std::string& column) {
  const std::vector<std::string> row = row_cells(out, "cornell_box.gltf", path);
  // The header row names the columns.
  const std::vector<std::string> names = row_cells(out, "scene", "path");
  for (size_t i = 0; i < names.size() && i < row.size(); ++i) {
    if (names[i] == column) return std::strtod(row[i].c_str(), nullptr);
  }
  ADD_FAILURE() << "no column '" << column << "' for path " << path << " in\n" << out;
  return -1.0;
}

TEST(BenchCliTest, EveryPathHasItsRawBaselineAndRatios) {
  const CliRun run = bench(
      "scenes/cornell_box.gltf --width 32 --height 24 --frames 3 --warmup 1 --rays 16 "
      "--grids 2x2x2 --paths fused,split");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* path : {"fused", "split"}) {
    const double total = cell(run.out, path, "field total");
    const double raw = cell(run.out, path, "raw trace");
    const double ratio = cell(run.out, path, "update / raw");
    const double primary = cell(run.out, path, "primary");
    const double primary_raw = cell(run.out, path, "primary raw");
    const double primary_ratio = cell(run.out, path, "primary / raw");
    std::printf("%s: field total %.3f ms, raw %.3f ms, ratio %.2f; primary %.3f / %.3f = %.2f\n",
                path, total, raw, ratio, primary, primary_raw, primary_ratio);
    // Control: the baselines ran and took time (a missing pass would print 0 or a dash).
    EXPECT_GT(raw, 0.0) << run.out;
    EXPECT_GT(primary_raw, 0.0) << run.out;
    // The ratios follow from the printed times: 3 decimals each (0.0005 on both), 2 for the
    // ratio (0.005).
    EXPECT_NEAR(ratio, total / raw, 0.005 + 0.0005 * (1.0 + ratio) / raw) << run.out;
    EXPECT_NEAR(primary_ratio, primary / primary_raw,
                0.005 + 0.0005 * (1.0 + primary_ratio) / primary_raw)
        << run.out;
  }
}

TEST(BenchCliTest, BadFlagsAreNamed) {
  const CliRun paths = bench("scenes/cornell_box.gltf --paths fused,bogus");
  EXPECT_NE(paths.exit_code, 0);
  EXPECT_NE(paths.err.find("--paths: 'bogus' is not fused or split"), std::string::npos)
      << paths.err;
  const CliRun rays = bench("scenes/cornell_box.gltf --rays 0");
  EXPECT_NE(rays.exit_code, 0);
  EXPECT_NE(rays.err.find("rays_per_probe must be in [1, 1024] (got 0)"), std::string::npos)
      << rays.err;
}

}  // namespace
}  // namespace ddgi::test
