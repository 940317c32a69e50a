// Helpers for multi-process service tests: run the juggle binary as a child process with its
// output in a file, find a free loopback port, poll the learner's /metrics.
#ifndef JUGGLE_TESTS_SERVICE_TEST_UTIL_H_
#define JUGGLE_TESTS_SERVICE_TEST_UTIL_H_

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include <fcntl.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/http_server.h"

namespace juggle::testing {

// A child process running `juggle <args>` (or another program); killed (SIGKILL) on
// destruction if still running.
class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& args, const std::string& log_path)
      : ChildProcess(JUGGLE_BINARY, args, log_path) {}
  // Runs `binary` (a path) with `args`; stdout and stderr appended to `log_path`.
  ChildProcess(std::string binary, const std::vector<std::string>& args,
               const std::string& log_path) {
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      std::vector<char*> argv;
      argv.push_back(binary.data());
      std::vector<std::string> copy = args;
      for (std::string& a : copy) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(binary.c_str(), argv.data());
      ::_exit(127);
    }
  }
  ~ChildProcess() {
    if (running()) Kill(SIGKILL);
    Wait();
  }
  void Kill(int sig) { if (pid_ > 0) ::kill(pid_, sig); }
  bool running() {
    if (pid_ <= 0 || exited_) return false;
    int status;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      status_ = status;
      return false;
    }
    return true;
  }
  // Waits up to `seconds` for exit; returns the exit code (-1 if still running or signalled).
  int Wait(double seconds = 30) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(int(seconds * 1000));
    while (running() && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (!exited_) return -1;
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
  }
  int pid() const { return pid_; }

 private:
  int pid_ = -1;
  bool exited_ = false;
  int status_ = 0;
};

// The full path of `program` found in $PATH, or "" when it is not installed.
inline std::string FindProgram(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path == nullptr ? "/usr/bin:/bin" : path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

// A loopback port nothing listens on now, drawn below the kernel's ephemeral range
// (ip_local_port_range): a port the kernel hands out itself can be handed again to any client
// socket before the server under test binds it (tests/deploy/lib.sh's free_port, same rule).
inline int FreePort() {
  int ephemeral_low = 32768;
  if (std::ifstream range("/proc/sys/net/ipv4/ip_local_port_range"); range) range >> ephemeral_low;
  std::random_device entropy;  // ports only; never seeds anything the tests compare
  std::uniform_int_distribution<int> draw(10000, std::max(10001, ephemeral_low) - 1);
  for (int attempt = 0; attempt < 200; ++attempt) {
    const int port = draw(entropy);
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(static_cast<uint16_t>(port));
    const bool bound = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0;
    ::close(fd);
    if (bound) return port;
  }
  std::abort();  // 200 busy ports in a row: the machine is not one a test can run on
}

// The value of an unlabelled metric (or a full `name{labels}` series) from /metrics; nullopt
// if the server does not answer or lacks the series.
inline std::optional<double> ScrapeMetric(int port, const std::string& series) {
  absl::StatusOr<std::string> body = HttpGet(port, "/metrics");
  if (!body.ok()) return std::nullopt;
  std::istringstream in(*body);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(series + " ", 0) == 0) return std::stod(line.substr(series.size() + 1));
  }
  return std::nullopt;
}

// Polls `predicate` every 100 ms for up to `seconds`.
inline bool WaitFor(const std::function<bool()>& predicate, double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(int(seconds * 1000));
  while (std::chrono::steady_clock::now() < until) {
    if (predicate()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return predicate();
}

}  // namespace juggle::testing

#endif  // JUGGLE_TESTS_SERVICE_TEST_UTIL_H_
