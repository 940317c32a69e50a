// Tests only: a fixture for a planning task of a shipped config (planner/tasks.cc), with one
// episode run from an env seed by the receding-horizon planner, by replayed actions or with zero
// action, and the checks every task owes: actions that depend only on the planner's seed, cost
// terms that add up. Header-only; used by the football tasks' tests.
#ifndef JUGGLE_PLANNER_TESTING_SHIPPED_TASK_TEST_H_
#define JUGGLE_PLANNER_TESTING_SHIPPED_TASK_TEST_H_

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/planner_config.h"
#include "planner/receding_horizon.h"
#include "planner/tasks.h"

namespace juggle::planner::testing {

// One episode: how it ended, its metrics, the actions that made it and the final qpos.
struct Episode {
  Outcome end = Outcome::kRunning;
  std::vector<NamedValue> metrics;
  std::vector<float> actions;
  std::vector<double> final_qpos;

  // The metric `name`, or `missing` when the episode did not report it.
  double Metric(const std::string& name, double missing = 0) const {
    for (const NamedValue& m : metrics) {
      if (m.name == name) return m.value;
    }
    return missing;
  }
};

class ShippedTaskTest : public ::testing::Test {
 protected:
  // Loads `config` and makes its spec and its planning task; fails the test on error.
  void Use(absl::StatusOr<LoadedConfig> config) {
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *std::move(config);
    ASSERT_TRUE(ValidatePlannerConfig(config_).ok()) << ValidatePlannerConfig(config_);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = *spec;
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    absl::StatusOr<std::shared_ptr<const PlanningTask>> task =
        MakePlanningTask(spec_, config_.run.planner());
    ASSERT_TRUE(task.ok()) << task.status();
    task_ = *task;
  }

  // One episode from env seed Rng(`seed`): with `planner`, with `replay`'s actions, or with
  // zero action.
  Episode Run(uint64_t seed, RecedingHorizonPlanner* planner,
              const std::vector<float>* replay = nullptr) {
    const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    Episode e;
    std::vector<float> a(spec_->act_dim(), 0.0f);
    for (int step = 0; step < 1000 && e.end == Outcome::kRunning; ++step) {
      if (planner != nullptr) {
        EXPECT_TRUE(planner->Act(*env, a.data()).ok());
      }
      if (replay != nullptr) std::copy_n(replay->begin() + step * a.size(), a.size(), a.begin());
      e.actions.insert(e.actions.end(), a.begin(), a.end());
      e.end = env->Step(a.data(), *walk_).outcome;
    }
    env->AppendEpisodeMetrics(&e.metrics);
    e.final_qpos.assign(env->data()->qpos, env->data()->qpos + spec_->model()->nq);
    return e;
  }

  // The config's planner settings with `seed`.
  config::PlannerConfig Settings(uint64_t seed = 1) const {
    config::PlannerConfig p = config_.run.planner();
    p.set_seed(seed);
    return p;
  }

  // A small search (and a small rescue, where the config has one) from env seed `seed`: the same
  // planner seed gives the same actions on 1 and 2 threads, another planner seed other actions.
  void ExpectActionsDependOnlyOnTheSeed(uint64_t seed) {
    config::PlannerConfig small = Settings(1);
    small.set_samples(6);
    small.set_iterations(2);
    // A config's rescue stays on, as small (the small search is often in trouble).
    small.mutable_rescue()->set_samples(8);
    small.mutable_rescue()->set_iterations(2);
    RolloutPool one(spec_, 1), two(spec_, 2);
    RecedingHorizonPlanner a(task_, small, &one, 0), b(task_, small, &two, 0);
    config::PlannerConfig other = small;
    other.set_seed(2);
    RecedingHorizonPlanner c(task_, other, &one, 0);
    const Episode first = Run(seed, &a);
    EXPECT_EQ(Run(seed, &b).actions, first.actions);
    EXPECT_NE(Run(seed, &c).actions, first.actions);
  }

  // Scores plan `theta` over up to `steps` control steps from env seed `seed`: the terms add up
  // to the total, one per name. Returns the finished scorer (partial() is the total).
  std::unique_ptr<RolloutScorer> ExpectTermsAddUpToTheCost(uint64_t seed,
                                                           const std::vector<double>& theta,
                                                           int steps) {
    const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    std::unique_ptr<RolloutScorer> scorer = task_->NewScorer();
    scorer->Begin(*env);
    std::vector<float> a(spec_->act_dim());
    StepResult r;
    for (int step = 0; step < steps && r.outcome == Outcome::kRunning; ++step) {
      task_->Action(*env, theta.data(), {step, 0}, nullptr, a.data());
      r = env->Step(a.data(), *walk_);
      scorer->AfterStep(*env, a.data(), r);
    }
    const double total = scorer->Finish(*env);
    double sum = 0;
    for (double t : scorer->terms()) sum += t;
    EXPECT_NEAR(sum, total, 1e-9 * std::max(1.0, total));
    EXPECT_EQ(scorer->terms().size(), task_->term_names().size());
    return scorer;
  }

  LoadedConfig config_;
  std::shared_ptr<const EnvSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  std::shared_ptr<const PlanningTask> task_;
};

}  // namespace juggle::planner::testing

#endif  // JUGGLE_PLANNER_TESTING_SHIPPED_TASK_TEST_H_
