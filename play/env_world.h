// An env of any registered family driven by a controller (a policy, the zero action or the
// planner: app/controller_factory.h), as the live page plays it. With a control graph the
// page's skill choice steers the adaptive walk (play/steering.h); the walk's counts stay at
// their base weights (nothing is learned while playing). Thread-compatible.
#ifndef JUGGLE_PLAY_ENV_WORLD_H_
#define JUGGLE_PLAY_ENV_WORLD_H_

#include <memory>
#include <string>
#include <vector>

#include "common/adaptive_walk.h"
#include "envs/env.h"
#include "eval/controller.h"
#include "planner/planner_controller.h"
#include "play/play_world.h"

namespace juggle::play {

class EnvWorld final : public PlayWorld {
 public:
  // `planner`, if not null, is the controller itself seen as the planner (its re-plans shown).
  // REQUIRES: the spec has at least one ball body (BallBodies).
  EnvWorld(std::shared_ptr<const EnvSpec> spec, std::unique_ptr<Controller> controller,
           planner::PlannerController* planner, uint64_t run_seed);

  std::string family() const override { return spec_->family(); }
  const mjModel* model() const override { return spec_->model(); }
  const mjData* data() const override { return env_->data(); }
  double control_dt() const override { return spec_->control_dt(); }
  void Restart(uint64_t seed) override;
  bool Step() override;
  absl::Status Poke(const std::array<double, 3>& impulse) override;
  absl::Status Choose(const std::string& name) override;
  nlohmann::json Options() const override;
  void AppendStatus(nlohmann::json* status) const override;

  const Env& env() const { return *env_; }
  // The planner's budget per re-plan as the page shows it ("16 samples x 3 iterations").
  void set_budget(std::string budget) { budget_ = std::move(budget); }
  // The node the skill choice steers toward, or "" (the walk chooses).
  const std::string& chosen() const { return chosen_; }

 private:
  std::shared_ptr<const EnvSpec> spec_;
  std::unique_ptr<Controller> controller_;
  planner::PlannerController* planner_;
  uint64_t run_seed_;
  AdaptiveWalk walk_;
  std::unique_ptr<Env> env_;
  std::vector<float> obs_, action_;
  std::vector<int> balls_;
  std::string chosen_;
  std::string budget_;
  std::string outcome_;  // the episode's end ("" while it runs)
  uint64_t seed_ = 0;
  int64_t replans_ = 0;
  planner::ReplanReport last_replan_;
  bool has_replan_ = false;
};

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_ENV_WORLD_H_
