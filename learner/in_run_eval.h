// The in-run evaluation (RunConfig.evaluation): when due, runs the current policy's mean action
// on held-out seeds (eval/episode_runner.h) and summarizes the juggles distribution. Its envs
// and RNG streams are its own, so training is unchanged by it. Thread-compatible: the training
// thread calls it between iterations.
#ifndef JUGGLE_LEARNER_IN_RUN_EVAL_H_
#define JUGGLE_LEARNER_IN_RUN_EVAL_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "envs/env.h"
#include "eval/summary.h"

namespace juggle {

// One evaluation: where the run was and what the policy did.
struct InRunEvaluation {
  int64_t iteration = 0;
  int64_t samples = 0;        // trained on so far
  double train_seconds = 0;   // wall time of training so far (evaluations included)
  double eval_seconds = 0;    // wall time this evaluation took
  EvalSummary summary;
  std::vector<int> juggles;   // per episode, in seed order (the distribution's raw values)
  std::string ToJson() const;    // one metrics.jsonl line, "event": "eval"
  std::string ToShort() const;   // "12.3 min: median 4 juggles (p90 9)"
};

class InRunEvaluator {
 public:
  // Builds the evaluation's spec (episodes up to evaluation.max_seconds). Errors as
  // CreateEnvSpec. Disabled (enabled() false) when neither period is set.
  static absl::StatusOr<std::unique_ptr<InRunEvaluator>> Create(const LoadedConfig& config);

  bool enabled() const { return every_minutes_ > 0 || every_iterations_ > 0; }
  // Due after `iteration` at `train_seconds` (the first is due one period in).
  bool Due(int64_t iteration, double train_seconds) const;
  // Evaluates `policy`; marks the period done.
  InRunEvaluation Run(const EigenPolicy& policy, int64_t iteration, int64_t samples,
                      double train_seconds);

 private:
  InRunEvaluator() = default;
  std::shared_ptr<const EnvSpec> spec_;
  config::EvaluationConfig config_;
  double every_minutes_ = 0;
  int every_iterations_ = 0;
  double last_seconds_ = 0;
  int64_t last_iteration_ = 0;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_IN_RUN_EVAL_H_
