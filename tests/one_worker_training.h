// Test helper: trains a started LearnerServer with one in-process worker (4 envs, 1 thread)
// until the server's own stop condition (e.g. LearnerOptions::max_iterations), then stops the
// worker and shuts the server down. Returns Train's status.
#ifndef JUGGLE_TESTS_ONE_WORKER_TRAINING_H_
#define JUGGLE_TESTS_ONE_WORKER_TRAINING_H_

#include <atomic>
#include <thread>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "learner/learner_server.h"
#include "worker/worker_client.h"

namespace juggle {

inline absl::Status TrainWithOneWorker(LearnerServer& server) {
  std::atomic<bool> stop{false}, workers_stop{false};
  std::thread worker([&] {
    WorkerOptions wo;
    wo.learner_address = absl::StrCat("127.0.0.1:", server.port());
    wo.num_envs = 4;
    wo.num_threads = 1;
    wo.requested_slot = 0;
    wo.stop = &workers_stop;
    wo.verbose = false;
    RunWorker(wo).IgnoreError();
  });
  const absl::Status trained = server.Train(&stop);
  workers_stop = true;
  worker.join();
  server.Shutdown();
  return trained;
}

}  // namespace juggle

#endif  // JUGGLE_TESTS_ONE_WORKER_TRAINING_H_
