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
