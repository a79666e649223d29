#include "tests/service/server_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

extern char** environ;

namespace ddgi::test {
namespace {
using Clock = std::chrono::steady_clock;
std::atomic<int> next_process{0};
}  // namespace

ServerProcess::ServerProcess(const std::vector<std::string>& extra) {
  port_file_ = testing::TempDir() + "/ddgi_port_" + std::to_string(::getpid()) + "_" +
               std::to_string(next_process.fetch_add(1));
  std::remove(port_file_.c_str());
  std::vector<std::string> args = {
      DDGI_SERVER_EXECUTABLE, "--listen", "127.0.0.1:0",  "--port-file",        port_file_,
      "--metrics-port",       "-1",       "--scene-root", DDGI_TEST_SCENE_ROOT, "--validation"};
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  EXPECT_EQ(posix_spawn(&pid_, argv[0], nullptr, nullptr, argv.data(), environ), 0);
}

ServerProcess::~ServerProcess() {
  if (pid_ > 0 && !exited_) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  std::remove(port_file_.c_str());
}

int ServerProcess::port(double timeout_seconds) {
  const auto end = Clock::now() + std::chrono::duration<double>(timeout_seconds);
  while (Clock::now() < end) {
    std::ifstream file(port_file_);
    int port = 0;
    if (file >> port && port > 0) return port;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return 0;
}

void ServerProcess::signal(int number) {
  ::kill(pid_, number);
}

int ServerProcess::wait(double timeout_seconds) {
  const auto end = Clock::now() + std::chrono::duration<double>(timeout_seconds);
  while (Clock::now() < end) {
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return -1;
}

}  // namespace ddgi::test
