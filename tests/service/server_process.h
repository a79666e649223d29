// A real ddgi-server process on a free loopback port (its --port-file tells which), for tests of
// what only a process shows: signals, exit codes, and process-wide gRPC settings such as
// reflection (its plugin, once registered, applies to every server a process builds).
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace ddgi::test {

class ServerProcess {
 public:
  // Starts DDGI_SERVER_EXECUTABLE on the test scenes with validation on, plus `extra` flags.
  explicit ServerProcess(const std::vector<std::string>& extra);
  ~ServerProcess();  // SIGKILL when still running
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  // The port, once the server wrote it (0 on timeout).
  int port(double timeout_seconds = 60.0);
  void signal(int number);
  // The exit status, or -1 when the process is still running after `timeout_seconds`.
  int wait(double timeout_seconds);

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  std::string port_file_;
};

}  // namespace ddgi::test
