// The planner as an evaluation controller (eval/controller.h): what `--controller=planner`
// runs in `juggle eval`, `juggle render` and `juggle simulate`. One SoccerPlanner per env (by
// identity: batches may be compacted as episodes end; its random stream is the order in which
// the env was first seen), all sharing one rollout pool of RunConfig.planner.threads threads.
// Thread-compatible.
#ifndef JUGGLE_PLANNER_PLANNER_CONTROLLER_H_
#define JUGGLE_PLANNER_PLANNER_CONTROLLER_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "eval/controller.h"
#include "planner/rollout_pool.h"
#include "planner/soccer_planner.h"

namespace juggle::planner {

// OK, or INVALID_ARGUMENT "file:line:col: planner.<field>: ..." for settings the schema's
// ranges allow but the run does not: a horizon longer than the episode, more body knots than
// horizon steps, a family the planner cannot drive.
absl::Status ValidatePlannerConfig(const LoadedConfig& config);

// Lays `text` (text-format PlannerConfig fields, e.g. "samples: 8 iterations: 2") over
// config->run.planner; empty text changes nothing. INVALID_ARGUMENT "--planner-set:1:col: ..."
// for text that does not parse or a value out of range.
absl::Status ApplyPlannerSettings(const std::string& text, LoadedConfig* config);

class PlannerController final : public Controller {
 public:
  // Validates config.run.planner (ValidatePlannerConfig) for `spec` (made from `config`).
  static absl::StatusOr<std::unique_ptr<PlannerController>> Create(
      std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config);

  // REQUIRES: envs of the spec given to Create (a foreign env aborts: programmer error).
  void Act(const Env* const* envs, const float* obs, int n, float* actions) override;
  std::string name() const override { return "planner"; }

  // Totals over every slot's planner.
  PlannerTotals totals() const;
  // Called after every re-plan (the env's planner stream, report): progress lines.
  void set_on_replan(std::function<void(int, const ReplanReport&)> f) { on_replan_ = std::move(f); }

 private:
  PlannerController(std::shared_ptr<const soccer_juggle::JuggleSpec> spec,
                    const config::PlannerConfig& config);

  std::shared_ptr<const soccer_juggle::JuggleSpec> spec_;
  config::PlannerConfig config_;
  RolloutPool pool_;
  std::vector<std::unique_ptr<SoccerPlanner>> planners_;  // in the order envs were first seen
  absl::flat_hash_map<const Env*, int> planner_of_;
  std::function<void(int, const ReplanReport&)> on_replan_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_PLANNER_CONTROLLER_H_
