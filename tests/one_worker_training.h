// Test helpers: the options of a tiny learner run, and training a started LearnerServer with
// one in-process worker (4 envs, 1 thread) until the server's own stop condition (e.g.
// LearnerOptions::max_iterations), then stopping the worker and shutting the server down.
#ifndef JUGGLE_TESTS_ONE_WORKER_TRAINING_H_
#define JUGGLE_TESTS_ONE_WORKER_TRAINING_H_

#include <atomic>
#include <string>
#include <thread>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "envs/registry.h"
#include "gtest/gtest.h"
#include "learner/learner_server.h"
#include "worker/worker_client.h"

namespace juggle {

// Options of a learner on tests/data/tiny_right_foot.textproto in `run_dir`, on a free loopback
// port, stopping after `iterations`, with an in-run evaluation of `episodes` 2-second episodes
// every `evaluate_every` iterations (0: none).
inline LearnerOptions TinyRunOptions(const std::string& run_dir, int iterations,
                                     int evaluate_every, int episodes = 3) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig("tests/data/tiny_right_foot.textproto");
  EXPECT_TRUE(config.ok()) << config.status();
  config::EvaluationConfig* e = config->run.mutable_evaluation();
  e->set_every_minutes(0);
  e->set_every_iterations(evaluate_every);
  e->set_episodes(episodes);
  e->set_max_seconds(2);
  LearnerOptions o;
  o.config = *config;
  o.run_dir = run_dir;
  o.port = 0;
  o.listen_all_interfaces = false;
  o.max_iterations = iterations;
  return o;
}

// `labeller_factory`: the worker's expert for runs that ask for labels (none by default).
inline absl::Status TrainWithOneWorker(LearnerServer& server,
                                       LabellerFactory labeller_factory = nullptr) {
  std::atomic<bool> stop{false}, workers_stop{false};
  std::thread worker([&] {
    WorkerOptions wo;
    wo.learner_address = absl::StrCat("127.0.0.1:", server.port());
    wo.num_envs = 4;
    wo.num_threads = 1;
    wo.requested_slot = 0;
    wo.stop = &workers_stop;
    wo.verbose = false;
    wo.labeller_factory = labeller_factory;
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
