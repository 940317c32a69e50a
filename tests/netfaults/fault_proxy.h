// A fault-injecting TCP proxy for the network-fault tests (docs/reliability.md, "Network
// faults"): it listens on a port, connects each accepted client to one target, and forwards
// bytes both ways, adding what a network does to them, changeable while traffic flows:
//
//   - latency with jitter per direction: every read segment is delivered `latency ± jitter`
//     seconds after it was read (uniform jitter), never before the segment read before it;
//   - loss as dropped and reset connections (the proxy's stand-in for packet loss: this
//     kernel has no netem): each forwarded segment resets its connection (RST to both peers)
//     with `reset_probability`, each accepted connection is reset at once with
//     `refuse_probability`;
//   - a one-way partition per direction (`pause`): that direction's bytes are held, unread,
//     as a blackholed link holds them (the sender's TCP stalls on an unacknowledged window);
//     they flow again when the pause is lifted, as after a heal;
//   - a stalled peer (`stall_new`): new connections are accepted and never answered (no
//     connection to the target, nothing read), until their client gives up and closes.
//
// Deterministic for a seed: every random draw comes from a generator seeded with (seed,
// connection number, direction), connection numbers counting accepts from 0. (Which draw
// falls on which bytes depends on how the peers' writes are split into reads.)
//
// Thread-safety: every public method may be called from any thread while traffic flows.
// Threads: one accepting, two per connection (one per direction).
#ifndef JUGGLE_TESTS_NETFAULTS_FAULT_PROXY_H_
#define JUGGLE_TESTS_NETFAULTS_FAULT_PROXY_H_

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"

namespace juggle::netfaults {

struct DirectionFaults {
  double latency_s = 0;  // added one-way delay
  double jitter_s = 0;   // ± uniform around latency_s (delivery never earlier than the read)
  bool paused = false;   // nothing read or delivered in this direction (one-way partition)
};

struct Faults {
  DirectionFaults upstream;    // client -> target
  DirectionFaults downstream;  // target -> client
  double reset_probability = 0;   // per forwarded segment, either direction
  double refuse_probability = 0;  // per accepted connection
  bool stall_new = false;         // accept new connections, never answer them
};

// Parses one control line into `faults` (the binary's stdin and tests use it):
//   latency up|down|both SECONDS [JITTER]   pause up|down|both   resume up|down|both
//   reset_probability P   refuse_probability P   stall_new on|off   heal (no faults)
// INVALID_ARGUMENT naming the line otherwise.
absl::Status ApplyControlLine(const std::string& line, Faults* faults);
// A one-line description of `faults` ("up 0.100±0.020 s, down paused, reset 5%, ...").
std::string Describe(const Faults& faults);

class FaultProxy {
 public:
  struct Stats {
    int64_t accepted = 0;     // connections accepted (stalled and refused ones included)
    int64_t open = 0;         // connections open now
    int64_t resets = 0;       // connections reset by reset_probability / refuse_probability
    int64_t stalled = 0;      // connections accepted under stall_new
    int64_t bytes_up = 0;     // bytes delivered client -> target
    int64_t bytes_down = 0;   // bytes delivered target -> client
  };

  // Listens on listen_host:listen_port (0: any free port) and forwards to target_host:
  // target_port (IPv4 literals). UNAVAILABLE if it cannot listen.
  static absl::StatusOr<std::unique_ptr<FaultProxy>> Start(const std::string& listen_host,
                                                            int listen_port,
                                                            const std::string& target_host,
                                                            int target_port, uint64_t seed);
  // Closes every connection and joins every thread.
  ~FaultProxy();

  int port() const { return port_; }
  // Applies to every connection, existing ones included, from their next read on.
  void SetFaults(const Faults& faults);
  Faults faults() const;
  Stats stats() const;
  // Resets (RST) every open connection now: a middlebox dropping its state.
  void ResetAll();

 private:
  struct Connection;
  FaultProxy(int listen_fd, int port, std::string target_host, int target_port, uint64_t seed);
  void AcceptLoop();
  void Pump(const std::shared_ptr<Connection>& c, bool upstream);
  void Reap() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);

  const int listen_fd_;
  const int port_;
  const std::string target_host_;
  const int target_port_;
  const uint64_t seed_;
  std::atomic<bool> stop_{false};
  mutable absl::Mutex mu_;
  Faults faults_ ABSL_GUARDED_BY(mu_);
  std::vector<std::shared_ptr<Connection>> connections_ ABSL_GUARDED_BY(mu_);
  int64_t accepted_ ABSL_GUARDED_BY(mu_) = 0;
  int64_t stalled_ ABSL_GUARDED_BY(mu_) = 0;
  std::atomic<int64_t> resets_{0}, bytes_up_{0}, bytes_down_{0};
  std::thread accept_thread_;
};

}  // namespace juggle::netfaults

#endif  // JUGGLE_TESTS_NETFAULTS_FAULT_PROXY_H_
