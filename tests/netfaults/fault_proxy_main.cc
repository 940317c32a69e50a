// fault_proxy: the test tree's fault-injecting TCP proxy as a program (fault_proxy.h), for
// running a fault schedule by hand. Reads control lines on stdin (see ApplyControlLine; also
// "stats" and "reset_all"), prints the faults after each; exits at the end of stdin.
//   fault_proxy --listen=127.0.0.1:6000 --target=127.0.0.1:50051 --seed=7
#include <cstdio>
#include <iostream>
#include <string>

#include "tests/netfaults/fault_proxy.h"

namespace {

bool HostPort(const std::string& text, std::string* host, int* port) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos) return false;
  *host = text.substr(0, colon);
  try {
    *port = std::stoi(text.substr(colon + 1));
  } catch (...) {
    return false;
  }
  return *port >= 0 && *port <= 65535;
}

}  // namespace

int main(int argc, char** argv) {
  std::string listen = "127.0.0.1:0", target;
  uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--listen=", 0) == 0) listen = a.substr(9);
    else if (a.rfind("--target=", 0) == 0) target = a.substr(9);
    else if (a.rfind("--seed=", 0) == 0) seed = std::stoull(a.substr(7));
    else {
      std::fprintf(stderr, "usage: fault_proxy --target=HOST:PORT [--listen=HOST:PORT] [--seed=N]\n");
      return 2;
    }
  }
  std::string listen_host, target_host;
  int listen_port = 0, target_port = 0;
  if (!HostPort(listen, &listen_host, &listen_port) || !HostPort(target, &target_host, &target_port)) {
    std::fprintf(stderr, "error: --listen and --target must be HOST:PORT (IPv4)\n");
    return 2;
  }
  auto proxy = juggle::netfaults::FaultProxy::Start(listen_host, listen_port, target_host,
                                                    target_port, seed);
  if (!proxy.ok()) {
    std::fprintf(stderr, "error: %s\n", std::string(proxy.status().message()).c_str());
    return 1;
  }
  std::printf("fault_proxy: %s:%d -> %s, seed %lu\n", listen_host.c_str(), (*proxy)->port(),
              target.c_str(), static_cast<unsigned long>(seed));
  std::fflush(stdout);
  std::string line;
  while (std::getline(std::cin, line)) {
    if (line.empty()) continue;
    if (line == "stats") {
      const auto s = (*proxy)->stats();
      std::printf("accepted %ld open %ld resets %ld stalled %ld bytes_up %ld bytes_down %ld\n",
                  long(s.accepted), long(s.open), long(s.resets), long(s.stalled),
                  long(s.bytes_up), long(s.bytes_down));
    } else if (line == "reset_all") {
      (*proxy)->ResetAll();
    } else {
      juggle::netfaults::Faults f = (*proxy)->faults();
      if (absl::Status s = juggle::netfaults::ApplyControlLine(line, &f); !s.ok()) {
        std::fprintf(stderr, "error: %s\n", std::string(s.message()).c_str());
        continue;
      }
      (*proxy)->SetFaults(f);
      std::printf("faults: %s\n", juggle::netfaults::Describe(f).c_str());
    }
    std::fflush(stdout);
  }
  return 0;
}
