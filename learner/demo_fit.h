// Offline behaviour cloning of a demonstration buffer (planner-guided training,
// docs/learning.md): how well a student network can fit the planner's labels, and how well it
// generalizes to labels it was not shown. The rows are split in the order they were added: the
// newest `held_out` share is held out (consecutive states are alike, so a random split
// flatters the fit; it is an option). Errors are in the imitation loss's units: per action, the squared error
// divided by max(the training labels' variance, min_label_std²), averaged over actions.
#ifndef JUGGLE_LEARNER_DEMO_FIT_H_
#define JUGGLE_LEARNER_DEMO_FIT_H_

#include <cstdint>
#include <functional>
#include <vector>

#include "absl/status/statusor.h"
#include "common/flat_parameters.h"
#include "learner/demo_buffer.h"
#include "proto/policy.pb.h"

namespace juggle {

struct DemoFitOptions {
  double held_out = 0.2;     // the newest share of rows, not trained on
  int64_t rows = 0;          // > 0: only the oldest this many rows (buffers compared at one size)
  int obs_prefix = 0;        // > 0: only the first this many observation floats (an input ablation)
  // > 0: train on only the newest this many of the training rows (those just before the
  // held-out share): a learning curve against one held-out set. The error's per-action
  // weights still come from every training row, so the units do not change with it.
  int64_t train_rows = 0;
  // Hold out a random share instead (rows alike in time fall on both sides: an upper bound of
  // how well the student fits states like those it was shown).
  bool random_split = false;
  int epochs = 20;
  int minibatch = 256;
  double lr = 1e-3;          // Adam
  double min_label_std = 0.08;
  // > 0: each row's observation is extended by the label of the row added before it (its
  // state's predecessor in the same unroll of this many steps; zeros at an unroll's first
  // step): would the student fit the labels if it knew the teacher's previous action? Only for
  // a buffer that has not wrapped (rows in unrolls from row 0).
  int previous_label_unroll = 0;
  uint64_t seed = 1;         // torch's generator (initialization, minibatch order)
  int threads = 1;           // torch's intra-op threads
  std::vector<int> actions;  // actions reported one by one (RMS error, R²)
};

struct DemoFitEpoch {
  int epoch = 0;
  double train_error = 0;     // on all training rows after the epoch
  double held_out_error = 0;
  std::vector<double> action_rms;  // held out, per DemoFitOptions::actions
  std::vector<double> action_r2;   // held out: 1 − SSE/SST
  double seconds = 0;              // wall time since the start
};

// Trains the actor of `model` (the policy network, tanh output) on the older rows and reports
// every epoch to `progress` (if set); returns the reports. INVALID_ARGUMENT when the buffer
// holds too few rows for both parts or an action index is out of range.
// With `fitted`, the trained actor is written there as a worker's policy parameters
// (ExportActorParameters: actor, log-std, observation normalizer of the training rows).
absl::StatusOr<std::vector<DemoFitEpoch>> FitDemos(
    const DemoBuffer& demos, const config::ModelConfig& model, const DemoFitOptions& options,
    const std::function<void(const DemoFitEpoch&)>& progress = nullptr,
    FlatParameters* fitted = nullptr);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DEMO_FIT_H_
