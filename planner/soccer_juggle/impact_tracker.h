// How the foot that kicks moves into the ball (docs/planner.md, "Impact acceleration"): a
// property of the soccer env's kick, measured in planner rollouts (planner/soccer_juggle/cost.h)
// and of executed episodes (planner/impact_observer.h). Thread-compatible.
#ifndef JUGGLE_PLANNER_SOCCER_JUGGLE_IMPACT_TRACKER_H_
#define JUGGLE_PLANNER_SOCCER_JUGGLE_IMPACT_TRACKER_H_

#include <vector>

#include "envs/soccer_juggle/env.h"

namespace juggle::planner {

// How the body that kicks moved into the ball: at a cycle's first touch, its centre of mass's
// acceleration along the direction of the ball's velocity change (the impulse; gravity and the
// env's ball force taken out) over the control step before the touch (docs/planner.md,
// "Impact acceleration"). Negative: the foot decelerates into the ball, which damps apex
// errors from kick to kick. The touching body is the env's (JuggleEnvState.touched_body). A
// touch in the first step after Begin is measured against the velocities one step back at the
// first state's acceleration. A cycle already touched at Begin, or whose touch comes in the
// same step as its DOWN node, is not measured.
class ImpactTracker {
 public:
  // At the first state.
  void Begin(const soccer_juggle::JuggleEnv& env);
  // After each step: the acceleration (m/s²) when this step holds a cycle's first touch; NaN
  // otherwise.
  double AfterStep(const soccer_juggle::JuggleEnv& env);

 private:
  // The tracked bodies' centre-of-mass velocities (3 per body, world axes) at `qvel`.
  void BodyVelocities(const soccer_juggle::JuggleEnv& env, const double* qvel,
                      std::vector<double>* out);
  // The bodies some node allows to touch the ball, and their velocities one and two steps back.
  std::vector<int> bodies_;
  std::vector<double> velocity_[2];
  std::vector<double> jacobian_;  // scratch, 3 × nv
  double ball_velocity_[3] = {0, 0, 0};  // one step back
  bool was_touched_ = false;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_JUGGLE_IMPACT_TRACKER_H_
