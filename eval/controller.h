// What acts in an env during evaluation, rendering and the toss runtime: a policy's mean action,
// the zero-action baseline, or the planner (planner/planner_controller.h). Thread-compatible.
#ifndef JUGGLE_EVAL_CONTROLLER_H_
#define JUGGLE_EVAL_CONTROLLER_H_

#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "envs/env.h"

namespace juggle {

class Controller {
 public:
  virtual ~Controller() = default;
  // Actions [n, act_dim] for the envs `envs[0..n)` whose observations are `obs` [n, obs_dim].
  virtual void Act(const Env* const* envs, const float* obs, int n, float* actions) = 0;
  // "checkpoint", "zero_action", ...: how evaluation lines name the controller.
  virtual std::string name() const = 0;
};

// Zero feed-forward (soccer) or home targets (toss): the family's base controller alone.
class ZeroController final : public Controller {
 public:
  explicit ZeroController(int act_dim) : act_dim_(act_dim) {}
  void Act(const Env* const*, const float*, int n, float* actions) override {
    std::fill(actions, actions + static_cast<size_t>(n) * act_dim_, 0.0f);
  }
  std::string name() const override { return "zero_action"; }

 private:
  int act_dim_;
};

// A policy's mean action (no exploration noise). Optionally keeps the gate weights of every
// call for the paper's Eq. 4 statistics.
class PolicyController final : public Controller {
 public:
  explicit PolicyController(std::shared_ptr<const EigenPolicy> policy, bool keep_gates = false)
      : policy_(std::move(policy)), keep_gates_(keep_gates) {}
  void Act(const Env* const*, const float* obs, int n, float* actions) override {
    const RowMatrix mean = policy_->MeanActions(obs, n);
    std::copy(mean.data(), mean.data() + mean.size(), actions);
    if (keep_gates_) {
      const RowMatrix g = policy_->Gates(obs, n);
      if (g.cols() > 0) {
        gates_.conservativeResize(gates_.rows() + g.rows(), g.cols());
        gates_.bottomRows(g.rows()) = g;
      }
    }
  }
  std::string name() const override { return "checkpoint"; }
  // Gate weights of every observation acted on so far [N, K] (empty for an MLP).
  const RowMatrix& gates() const { return gates_; }

 private:
  std::shared_ptr<const EigenPolicy> policy_;
  bool keep_gates_;
  RowMatrix gates_;
};

// Makes the controller that acts in the envs of `spec` (built from `config`): a policy ignores
// both, the planner plans with them. For tools that build their env specs themselves.
using ControllerFactory = std::function<absl::StatusOr<std::unique_ptr<Controller>>(
    std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config)>;

}  // namespace juggle

#endif  // JUGGLE_EVAL_CONTROLLER_H_
