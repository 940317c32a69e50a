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
#include "proto/run_log.pb.h"

namespace juggle {

// The evaluation's record (the run log's "eval" line, proto/run_log.proto) from a summary,
// and back.
void SetSummary(const EvalSummary& summary, runlog::EvaluationRecord* record);
EvalSummary SummaryOf(const runlog::EvaluationRecord& record);
// "eval @12.3 min: median 4 juggles (p90 9, >=10: 20%)".
std::string EvaluationShort(const runlog::EvaluationRecord& record);

class InRunEvaluator {
 public:
  // Builds the evaluation's spec (episodes up to evaluation.max_seconds). Errors as
  // CreateEnvSpec. Disabled (enabled() false) when neither period is set.
  static absl::StatusOr<std::unique_ptr<InRunEvaluator>> Create(const LoadedConfig& config);

  bool enabled() const { return every_minutes_ > 0 || every_iterations_ > 0; }
  // Due after `iteration` at `train_seconds` (the first is due one period in).
  bool Due(int64_t iteration, double train_seconds) const;
  // Evaluates `policy`; marks the period done. The record's iteration, samples and train_s are
  // the arguments (the caller adds the evaluation's own time to train_s afterwards).
  runlog::EvaluationRecord Run(const EigenPolicy& policy, int64_t iteration, int64_t samples,
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
