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
