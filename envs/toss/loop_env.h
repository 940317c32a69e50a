// TossLoopEnv: in-loop training of a toss policy (toss.loop set). The env runs the two-arm
// pattern runtime (TossJuggler) on patterns drawn from loop.pattern; the learning policy drives
// the right arm whenever it is in the config task's mode, the frozen partner policies drive
// everything else. So the policy trains on exactly the states the runtime produces: catches
// that start in a throw's follow-through, throws that start from off-centre catches.
//
// An episode is one segment of the right arm in the task's mode:
//   CATCH  from the moment the hand is empty with a ball due at it, to the catch
//          (−w2·min(|z̄ − z|, 1), kCaught, one completion) or the failure of that ball: it drops
//          or the hand's beat comes without it (−w2, kDropped). Per step −w1·effort.
//   THROW  from the moment the hand holds a ball it will release, to the release at its beat
//          (−w4·|p̄ − p|² − w5·|v̄ − v|², kReleased; a completion if IsGoodThrow). Per step
//          −w3·effort.
// Reset advances the runtime with the partner policies to the next such segment; when the
// juggling run ends (any drop, a missed beat, loop.max_throws) a new run starts on a freshly
// drawn pattern (uniformly, or weighted by its recent failures: loop.weight_failures), or with
// probability loop.transition_fraction a transition run between two drawn patterns. With
// toss.base the actions are residuals on the base controllers (envs/toss/base_controller.h). A run that ends inside a segment for a reason that is not the segment's own
// failure truncates the episode (kTimeLimit, bootstrapped). Divergence ends it (kDiverged).
// Observations are the runtime's: S_catch / S_throw of the right arm.
#ifndef JUGGLE_ENVS_TOSS_LOOP_ENV_H_
#define JUGGLE_ENVS_TOSS_LOOP_ENV_H_

#include <memory>
#include <vector>

#include "common/rng.h"
#include "envs/env.h"
#include "envs/toss/juggler.h"
#include "envs/toss/spec.h"

namespace juggle::toss {

// The loop env's state of an episode: a copy of the runtime and the env's own variables.
class TossLoopSnapshot final : public EnvSnapshot {
 public:
  std::string family() const override { return "toss"; }
  std::shared_ptr<const TossJuggler> juggler;
  Rng rng{0};
  int steps = 0, completions = 0, runs_started = 0, run_pattern = -1;
  std::vector<double> failure_rate;
};

class TossLoopEnv : public juggle::Env {
 public:
  // REQUIRES: spec->in_loop().
  TossLoopEnv(std::shared_ptr<const TossSpec> spec, Rng rng);

  void Reset(const AdaptiveWalk& walk) override;
  StepResult Step(const float* action, const AdaptiveWalk& walk) override;
  void WriteObservation(float* obs) const override;
  int steps() const override { return steps_; }
  int completions() const override { return completions_; }
  mjData* data() override { return juggler_->mutable_world()->data(); }
  const mjData* data() const override { return juggler_->world().data(); }
  std::unique_ptr<EnvSnapshot> Snapshot() const override;
  absl::Status Restore(const EnvSnapshot& snapshot) override;

  // The runtime of the current juggling run (for tests).
  const TossJuggler& juggler() const { return *juggler_; }
  // Juggling runs started so far.
  int runs_started() const { return runs_started_; }
  // Recent failure rate of each loop pattern in this env (loop.weight_failures).
  const std::vector<double>& failure_rates() const { return failure_rate_; }

 private:
  bool TrainsThrow() const { return spec_->toss().task() == config::THROW; }
  // The right arm is in the task's mode.
  bool InSegment() const;
  void StartRun();
  int DrawPattern();
  StepResult CatchOutcome() const;
  StepResult ThrowOutcome();

  std::shared_ptr<const TossSpec> spec_;
  Rng rng_;
  std::unique_ptr<TossJuggler> juggler_;
  int steps_ = 0;
  int completions_ = 0;
  int runs_started_ = 0;
  std::vector<double> failure_rate_;  // per loop pattern
  int run_pattern_ = -1;              // the pattern the current run is scored on
};

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_LOOP_ENV_H_
