#include "tests/netfaults/fault_proxy.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <random>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle::netfaults {
namespace {

using Clock = std::chrono::steady_clock;
constexpr size_t kMaxPendingBytes = size_t{4} << 20;  // per direction; reading waits beyond
constexpr int kTickMs = 20;                           // how often loops look at faults and stop

uint64_t SplitMix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
// The generator of connection `number`'s stream `which` (0 up, 1 down, 2 its accept).
std::mt19937_64 StreamRng(uint64_t seed, int64_t number, int which) {
  return std::mt19937_64(SplitMix(SplitMix(seed) ^ SplitMix(static_cast<uint64_t>(number) * 3 + which)));
}

void NoDelay(int fd) {
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
}
// Closes `fd` with an RST instead of a FIN.
void CloseWithReset(int fd) {
  const linger l{1, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &l, sizeof(l));
  ::close(fd);
}
bool SendAll(int fd, const char* data, size_t n) {
  while (n > 0) {
    const ssize_t w = ::send(fd, data, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    data += w;
    n -= static_cast<size_t>(w);
  }
  return true;
}
sockaddr_in Address(const std::string& host, int port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  ::inet_pton(AF_INET, host.c_str(), &a.sin_addr);
  return a;
}

absl::Status Direction(const std::string& word, bool* up, bool* down) {
  *up = word == "up" || word == "both";
  *down = word == "down" || word == "both";
  if (!*up && !*down) return absl::InvalidArgumentError("direction must be up, down or both");
  return absl::OkStatus();
}

}  // namespace

absl::Status ApplyControlLine(const std::string& line, Faults* f) {
  std::istringstream in(line);
  std::string verb, arg;
  in >> verb;
  auto bad = [&](const std::string& why) {
    return absl::InvalidArgumentError(absl::StrCat("control line \"", line, "\": ", why));
  };
  auto probability = [&](double* p) -> absl::Status {
    double v = -1;
    if (!(in >> v) || v < 0 || v > 1) return bad("a probability in [0, 1] is expected");
    *p = v;
    return absl::OkStatus();
  };
  if (verb == "heal") {
    *f = Faults();
  } else if (verb == "latency" || verb == "pause" || verb == "resume") {
    bool up = false, down = false;
    in >> arg;
    if (absl::Status s = Direction(arg, &up, &down); !s.ok()) return bad(std::string(s.message()));
    double latency = 0, jitter = 0;
    if (verb == "latency") {
      if (!(in >> latency) || latency < 0 || latency > 600) return bad("latency in [0, 600] s expected");
      if (in >> jitter; jitter < 0 || jitter > latency) return bad("jitter in [0, latency] expected");
    }
    for (DirectionFaults* d : {up ? &f->upstream : nullptr, down ? &f->downstream : nullptr}) {
      if (d == nullptr) continue;
      if (verb == "latency") {
        d->latency_s = latency;
        d->jitter_s = jitter;
      } else {
        d->paused = verb == "pause";
      }
    }
  } else if (verb == "reset_probability") {
    return probability(&f->reset_probability);
  } else if (verb == "refuse_probability") {
    return probability(&f->refuse_probability);
  } else if (verb == "stall_new") {
    in >> arg;
    if (arg != "on" && arg != "off") return bad("stall_new on|off expected");
    f->stall_new = arg == "on";
  } else {
    return bad("unknown command (latency, pause, resume, reset_probability, "
               "refuse_probability, stall_new, heal)");
  }
  return absl::OkStatus();
}

std::string Describe(const Faults& f) {
  auto dir = [](const DirectionFaults& d) {
    if (d.paused) return std::string("paused");
    return absl::StrFormat("%.3f±%.3f s", d.latency_s, d.jitter_s);
  };
  return absl::StrFormat("up %s, down %s, reset %.1f%%/segment, refuse %.1f%%/connection%s",
                         dir(f.upstream), dir(f.downstream), 100 * f.reset_probability,
                         100 * f.refuse_probability, f.stall_new ? ", new connections stall" : "");
}

struct FaultProxy::Connection {
  int64_t number = 0;
  int client_fd = -1;
  int target_fd = -1;  // -1: a stalled connection
  std::atomic<bool> reset{false};
  std::atomic<int> running{0};  // pump threads still running
  std::thread up, down;
  bool done() const { return running.load() == 0; }
  void Finish() { running.fetch_sub(1); }
  // After both threads joined: closes the sockets (with RSTs after a reset).
  void Close() {
    if (up.joinable()) up.join();
    if (down.joinable()) down.join();
    if (reset) {
      CloseWithReset(client_fd);
      if (target_fd >= 0) CloseWithReset(target_fd);
    } else {
      ::close(client_fd);
      if (target_fd >= 0) ::close(target_fd);
    }
  }
};

absl::StatusOr<std::unique_ptr<FaultProxy>> FaultProxy::Start(const std::string& listen_host,
                                                               int listen_port,
                                                               const std::string& target_host,
                                                               int target_port, uint64_t seed) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in a = Address(listen_host, listen_port);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0 || ::listen(fd, 128) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    return absl::UnavailableError(
        absl::StrCat("fault proxy: cannot listen on ", listen_host, ":", listen_port, ": ", why));
  }
  socklen_t len = sizeof(a);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  return std::unique_ptr<FaultProxy>(
      new FaultProxy(fd, ntohs(a.sin_port), target_host, target_port, seed));
}

FaultProxy::FaultProxy(int listen_fd, int port, std::string target_host, int target_port,
                       uint64_t seed)
    : listen_fd_(listen_fd), port_(port), target_host_(std::move(target_host)),
      target_port_(target_port), seed_(seed) {
  accept_thread_ = std::thread([this] { AcceptLoop(); });
}

FaultProxy::~FaultProxy() {
  stop_ = true;
  accept_thread_.join();
  ::close(listen_fd_);
  std::vector<std::shared_ptr<Connection>> all;
  {
    absl::MutexLock lock(&mu_);
    all.swap(connections_);
  }
  for (auto& c : all) {
    // Unblocks a pump stuck in send() towards a peer that stopped reading.
    ::shutdown(c->client_fd, SHUT_RDWR);
    if (c->target_fd >= 0) ::shutdown(c->target_fd, SHUT_RDWR);
    c->Close();
  }
}

void FaultProxy::SetFaults(const Faults& faults) {
  absl::MutexLock lock(&mu_);
  faults_ = faults;
}

Faults FaultProxy::faults() const {
  absl::MutexLock lock(&mu_);
  return faults_;
}

FaultProxy::Stats FaultProxy::stats() const {
  Stats s;
  absl::MutexLock lock(&mu_);
  s.accepted = accepted_;
  s.stalled = stalled_;
  for (const auto& c : connections_) s.open += c->done() ? 0 : 1;
  s.resets = resets_;
  s.bytes_up = bytes_up_;
  s.bytes_down = bytes_down_;
  return s;
}

void FaultProxy::ResetAll() {
  absl::MutexLock lock(&mu_);
  for (const auto& c : connections_) {
    if (!c->done() && !c->reset.exchange(true)) ++resets_;
  }
}

void FaultProxy::Reap() {
  for (auto it = connections_.begin(); it != connections_.end();) {
    if ((*it)->done()) {
      (*it)->Close();
      it = connections_.erase(it);
    } else {
      ++it;
    }
  }
}

void FaultProxy::AcceptLoop() {
  while (!stop_) {
    pollfd p{listen_fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, 50);
    absl::MutexLock lock(&mu_);
    Reap();
    if (ready <= 0) continue;
    const int client = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) continue;
    NoDelay(client);
    auto c = std::make_shared<Connection>();
    c->number = accepted_++;
    c->client_fd = client;
    if (faults_.stall_new) {
      // Accepted by the kernel, never read or answered: waits for its client to hang up.
      ++stalled_;
      c->running = 1;
      c->up = std::thread([this, c] {
        while (!stop_ && !c->reset) {
          pollfd q{c->client_fd, POLLRDHUP, 0};
          if (::poll(&q, 1, kTickMs) > 0 && (q.revents & (POLLRDHUP | POLLHUP | POLLERR))) break;
        }
        c->Finish();
      });
      connections_.push_back(std::move(c));
      continue;
    }
    std::mt19937_64 rng = StreamRng(seed_, c->number, 2);
    if (faults_.refuse_probability > 0 &&
        std::uniform_real_distribution<double>(0, 1)(rng) < faults_.refuse_probability) {
      ++resets_;
      CloseWithReset(client);
      continue;
    }
    const int target = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const sockaddr_in a = Address(target_host_, target_port_);
    if (::connect(target, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) != 0) {
      ::close(target);
      CloseWithReset(client);  // the target is down: the client sees a reset, as from a router
      continue;
    }
    NoDelay(target);
    c->target_fd = target;
    c->running = 2;
    c->up = std::thread([this, c] { Pump(c, /*upstream=*/true); });
    c->down = std::thread([this, c] { Pump(c, /*upstream=*/false); });
    connections_.push_back(std::move(c));
  }
}

void FaultProxy::Pump(const std::shared_ptr<Connection>& c, bool upstream) {
  const int src = upstream ? c->client_fd : c->target_fd;
  const int dst = upstream ? c->target_fd : c->client_fd;
  std::atomic<int64_t>& delivered = upstream ? bytes_up_ : bytes_down_;
  std::mt19937_64 rng = StreamRng(seed_, c->number, upstream ? 0 : 1);
  std::uniform_real_distribution<double> unit(0, 1);
  struct Segment {
    Clock::time_point due;
    std::string bytes;
  };
  std::deque<Segment> pending;
  size_t pending_bytes = 0;
  bool src_closed = false;
  Clock::time_point last_due = Clock::now();
  std::vector<char> buf(64 << 10);
  while (!stop_ && !c->reset) {
    Faults f;
    {
      absl::MutexLock lock(&mu_);
      f = faults_;
    }
    const DirectionFaults& d = upstream ? f.upstream : f.downstream;
    auto now = Clock::now();
    // Deliver what is due (nothing while paused: held as a blackholed link holds it).
    while (!d.paused && !pending.empty() && pending.front().due <= now) {
      if (!SendAll(dst, pending.front().bytes.data(), pending.front().bytes.size())) {
        c->reset = true;  // the receiver is gone: its peer learns by a reset
        break;
      }
      delivered += static_cast<int64_t>(pending.front().bytes.size());
      pending_bytes -= pending.front().bytes.size();
      pending.pop_front();
    }
    if (c->reset) break;
    if (src_closed && pending.empty()) {
      ::shutdown(dst, SHUT_WR);  // pass the FIN on
      break;
    }
    int wait_ms = kTickMs;
    if (!d.paused && !pending.empty()) {
      const auto until = std::chrono::duration_cast<std::chrono::milliseconds>(pending.front().due - now);
      wait_ms = std::clamp(static_cast<int>(until.count()), 0, kTickMs);
    }
    if (d.paused || src_closed || pending_bytes >= kMaxPendingBytes) {
      std::this_thread::sleep_for(std::chrono::milliseconds(std::max(1, wait_ms)));
      continue;
    }
    pollfd p{src, POLLIN, 0};
    if (::poll(&p, 1, wait_ms) <= 0) continue;
    const ssize_t n = ::recv(src, buf.data(), buf.size(), 0);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      c->reset = true;  // reset by the peer: pass it on
      break;
    }
    if (n == 0) {
      src_closed = true;
      continue;
    }
    if (f.reset_probability > 0 && unit(rng) < f.reset_probability) {
      if (!c->reset.exchange(true)) ++resets_;
      break;
    }
    now = Clock::now();
    const double delay = std::max(0.0, d.latency_s + (d.jitter_s > 0 ? (2 * unit(rng) - 1) * d.jitter_s : 0));
    last_due = std::max(last_due, now + std::chrono::microseconds(static_cast<int64_t>(delay * 1e6)));
    pending.push_back({last_due, std::string(buf.data(), static_cast<size_t>(n))});
    pending_bytes += static_cast<size_t>(n);
  }
  c->Finish();
}

}  // namespace juggle::netfaults
