// Runs one of the project's executables as a user would (from the repository root, through the
// shell) and captures its exit code, stdout and stderr: the CLI tests of ddgi-render and
// ddgi-bench share it.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "encode/file_io.h"
#include "encode/png.h"

namespace ddgi::test {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// The cells of a markdown table row ("| a | b |"), trimmed; what the tools print their tables as.
inline std::vector<std::string> markdown_cells(const std::string& row) {
  std::vector<std::string> cells;
  std::istringstream parts(row);
  std::string cell;
  std::getline(parts, cell, '|');  // before the first bar
  while (std::getline(parts, cell, '|')) {
    const size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
    cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  return cells;
}

// The pixels of a plot's PNG (tools/plot_raster.h) with exactly the colour 0xRRGGBB: a series'
// markers (and its legend marker). -1 when the file does not decode.
inline int64_t plot_pixels_of_colour(const std::filesystem::path& png, uint32_t rgb) {
  const Result<std::vector<uint8_t>> bytes = encode::read_file(png.string());
  if (!bytes.ok()) return -1;
  const Result<encode::ImageRgba8> image = encode::decode_png(*bytes);
  if (!image.ok()) return -1;
  int64_t count = 0;
  for (size_t i = 0; i + 3 < image->pixels.size(); i += 4) {
    const uint32_t pixel = uint32_t(image->pixels[i]) << 16 | uint32_t(image->pixels[i + 1]) << 8 |
                           uint32_t(image->pixels[i + 2]);
    count += pixel == rgb ? 1 : 0;
  }
  return count;
}

// `executable` with `arguments` (shell words), run in DDGI_SOURCE_DIR; its output files go into
// `scratch` (which must exist).
inline CliRun run_cli(const std::string& executable, const std::string& arguments,
                      const std::filesystem::path& scratch) {
  const std::string command = std::string("cd '") + DDGI_SOURCE_DIR + "' && '" + executable + "' " +
                              arguments + " >'" + (scratch / "out.txt").string() + "' 2>'" +
                              (scratch / "err.txt").string() + "'";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(scratch / "out.txt"),
          slurp(scratch / "err.txt")};
}

}  // namespace ddgi::test
