// Tests only: the smallest planning task, proving that a task is a folder plus a registration
// (docs/planner.md, "Adding a planning task"). A point mass on a frictionless plane (two slide
// joints, two motors, MuJoCo) must reach a target and stop there. Its env family "point_mass"
// has exact snapshots; its task plans a piecewise-linear spline of the two actions with a knot
// every `knot_steps` control steps on a grid fixed to the episode, and scores the squared
// distance to the target per step, the effort and, at the horizon's end, distance and speed.
#ifndef JUGGLE_PLANNER_TESTING_POINT_MASS_H_
#define JUGGLE_PLANNER_TESTING_POINT_MASS_H_

#include <memory>
#include <string>
#include <vector>

#include "envs/env.h"
#include "envs/mujoco_model.h"
#include "planner/planning_task.h"

namespace juggle::planner::testing {

class PointMassSpec final : public EnvSpec {
 public:
  // Episodes of `max_steps` control steps of 20 ms (4 physics steps of 5 ms).
  static std::shared_ptr<const PointMassSpec> Create(int max_steps = 200);

  std::string family() const override { return "point_mass"; }
  int obs_dim() const override { return 4; }
  int act_dim() const override { return 2; }
  double control_dt() const override { return 0.02; }
  const ControlGraph& graph() const override { return graph_; }
  const mjModel* model() const override { return model_.get(); }
  std::vector<std::string> outcome_names() const override;
  std::unique_ptr<Env> NewEnv(Rng rng) const override;
  int max_steps() const { return max_steps_; }
  static constexpr int kSubsteps = 4;

 private:
  PointMassSpec(MjModelPtr model, int max_steps);
  MjModelPtr model_;
  ControlGraph graph_;
  int max_steps_;
};

struct PointMassTaskSettings {
  double target[2] = {0.3, -0.2};
  int horizon = 30;
  int knot_steps = 5;
  double sigma = 0.3;
  // Per-step weights: distance², effort (mean squared action); at the horizon's end:
  // terminal × (distance² + 0.1·speed²).
  double effort = 0.01;
  double terminal = 10;
};

class PointMassTask final : public PlanningTask {
 public:
  explicit PointMassTask(const PointMassTaskSettings& settings);
  std::string family() const override { return "point_mass"; }
  const SearchSpace& space() const override { return space_; }
  const SearchSpace& rescue_space() const override { return rescue_space_; }
  int horizon() const override { return settings_.horizon; }
  int KnotAtOrBefore(int step) const override {
    return step / settings_.knot_steps * settings_.knot_steps;
  }
  std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                            int cycles) const override;
  void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
              float* action) const override;
  std::unique_ptr<RolloutScorer> NewScorer() const override;
  std::vector<std::string> term_names() const override { return {"distance", "effort", "terminal"}; }
  int knots() const { return knots_; }
  const PointMassTaskSettings& settings() const { return settings_; }

 private:
  PointMassTaskSettings settings_;
  int knots_;
  SearchSpace space_, rescue_space_;
};

}  // namespace juggle::planner::testing

#endif  // JUGGLE_PLANNER_TESTING_POINT_MASS_H_
