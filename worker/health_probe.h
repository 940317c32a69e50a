// A one-shot check of the learner's gRPC health service (grpc.health.v1.Health/Check, service
// ""), over the same transport a worker uses (TLS when `security` says so). Container probes run
// it (`juggle-worker --probe`): Kubernetes' native gRPC probes cannot speak TLS.
#ifndef JUGGLE_WORKER_HEALTH_PROBE_H_
#define JUGGLE_WORKER_HEALTH_PROBE_H_

#include <string>

#include "absl/status/status.h"
#include "common/transport_security.h"

namespace juggle {

// OK when the learner at `address` answers SERVING within `timeout_s`. UNAVAILABLE when it
// answers another status; otherwise the call's gRPC status (DEADLINE_EXCEEDED, UNAVAILABLE, ...)
// with the address in the message.
absl::Status ProbeLearnerHealth(const std::string& address, const TransportSecurity& security,
                                double timeout_s);

}  // namespace juggle

#endif  // JUGGLE_WORKER_HEALTH_PROBE_H_
