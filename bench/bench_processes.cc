#include "bench/bench_processes.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "common/http_server.h"

namespace juggle {

SelfProcess::SelfProcess(const std::vector<std::string>& args, const std::string& log) {
  std::fflush(stdout);  // or the child's copy of the buffer is printed twice
  pid_ = ::fork();
  if (pid_ == 0) {
    FILE* f = std::freopen(log.c_str(), "a", stdout);
    if (f != nullptr) ::dup2(::fileno(stdout), 2);
    std::vector<char*> argv;
    std::string self = "/proc/self/exe";
    argv.push_back(self.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv("/proc/self/exe", argv.data());
    ::_exit(127);
  }
}

int SelfProcess::Stop(int sig) {
  if (pid_ <= 0) return -1;
  ::kill(pid_, sig);
  int status = 0;
  for (int i = 0; i < 600 && ::waitpid(pid_, &status, WNOHANG) == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

double SelfProcess::RssMb() const {
  std::ifstream in(absl::StrCat("/proc/", pid_, "/status"));
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return -1;
}

double SelfProcess::CpuSeconds() const {
  std::ifstream in(absl::StrCat("/proc/", pid_, "/stat"));
  std::string stat((std::istreambuf_iterator<char>(in)), {});
  const size_t close = stat.rfind(')');  // the command name may contain spaces
  if (close == std::string::npos) return -1;
  const std::vector<std::string> fields = absl::StrSplit(stat.substr(close + 2), ' ');
  if (fields.size() < 13) return -1;
  // Fields 14 and 15 of /proc/PID/stat (utime, stime), counted from after the name.
  return (std::stod(fields[11]) + std::stod(fields[12])) / double(::sysconf(_SC_CLK_TCK));
}

absl::StatusOr<LoadedConfig> LoadAsynchronousConfig(const std::string& path,
                                                    const std::string& bench) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(path);
  if (config.ok() && config->run.service().synchronous()) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": ", bench, " needs an asynchronous config"));
  }
  return config;
}

namespace {
// The unlabelled series Scrape reads, and where each goes.
const std::map<std::string, double Accounts::*> kScalarFields = {
    {"juggle_unrolls_accepted_total", &Accounts::accepted},
    {"juggle_unrolls_trained_total", &Accounts::trained},
    {"juggle_unrolls_held", &Accounts::held},
    {"juggle_unrolls_partial", &Accounts::partial},
    {"juggle_ingest_queue_chunks", &Accounts::queued_chunks},
    {"juggle_iterations_total", &Accounts::iterations},
    {"juggle_policy_version", &Accounts::version},
    {"juggle_workers_connected", &Accounts::workers},
    {"juggle_samples_total", &Accounts::samples},
    {"juggle_policy_lag_versions_sum", &Accounts::lag_sum},
    {"juggle_policy_lag_versions_count", &Accounts::lag_count},
    {"juggle_policy_broadcast_seconds_sum", &Accounts::broadcast_sum},
    {"juggle_policy_broadcast_seconds_count", &Accounts::broadcast_count},
};
}  // namespace

Accounts Scrape(int metrics_port) {
  Accounts a;
  absl::StatusOr<std::string> body = HttpGet(metrics_port, "/metrics");
  if (!body.ok()) return a;
  a.ok = true;
  std::istringstream in(*body);
  std::string line;
  auto value = [&](const std::string& l) { return std::stod(l.substr(l.rfind(' ') + 1)); };
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::string name = line.substr(0, line.find_first_of(" {"));
    if (const auto field = kScalarFields.find(name); field != kScalarFields.end()) {
      a.*(field->second) = value(line);
    } else if (name == "juggle_unrolls_dropped_total") {
      const size_t r = line.find("reason=\"");
      const std::string reason =
          r == std::string::npos ? "?" : line.substr(r + 8, line.find('"', r + 8) - r - 8);
      a.dropped_by_reason[reason] += value(line);
      a.dropped += value(line);
    }
  }
  return a;
}

int FreeLoopbackPort() {
  // Ask the kernel for a free port through a throwaway HTTP server.
  absl::StatusOr<std::unique_ptr<HttpServer>> s =
      HttpServer::Start(0, false, [](const HttpRequest&) { return HttpResponse{}; });
  if (!s.ok()) return 0;
  const int port = (*s)->port();
  (*s)->Stop();
  return port;
}

}  // namespace juggle
