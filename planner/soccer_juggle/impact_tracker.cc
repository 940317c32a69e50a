#include "planner/soccer_juggle/impact_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace juggle::planner {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;

void ImpactTracker::Begin(const JuggleEnv& env) {
  const JuggleSpec& spec = env.spec();
  const mjModel* m = spec.model();
  const mjData* d = env.data();
  bodies_.clear();
  for (int b = 1; b < m->nbody; ++b) {
    for (int n = 0; n < spec.graph().num_nodes(); ++n) {
      if (spec.node_runtime(n).contact_allowed[b]) {
        bodies_.push_back(b);
        break;
      }
    }
  }
  jacobian_.resize(3 * m->nv);
  was_touched_ = env.state().kick_touched;
  // One step back, at the state's acceleration (the env's last forward pass), so that a touch in
  // the rollout's first step is measured too, the same way for every candidate.
  std::vector<double> earlier(d->qvel, d->qvel + m->nv);
  mju_addToScl(earlier.data(), d->qacc, -spec.control_dt(), m->nv);
  BodyVelocities(env, earlier.data(), &velocity_[1]);
  BodyVelocities(env, d->qvel, &velocity_[0]);
  mju_copy3(ball_velocity_, d->qvel + spec.ball_dof());
}

void ImpactTracker::BodyVelocities(const JuggleEnv& env, const double* qvel,
                                   std::vector<double>* out) {
  const mjModel* m = env.spec().model();
  out->resize(3 * bodies_.size());
  for (size_t i = 0; i < bodies_.size(); ++i) {
    // The joint velocities are the step's end, the Jacobian of its last substep's start
    // (mj_step's kinematics): one substep of motion apart.
    mj_jacBodyCom(m, env.data(), jacobian_.data(), nullptr, bodies_[i]);
    mju_mulMatVec(out->data() + 3 * i, jacobian_.data(), qvel, 3, m->nv);
  }
}

double ImpactTracker::AfterStep(const JuggleEnv& env) {
  const JuggleSpec& spec = env.spec();
  const mjModel* m = spec.model();
  const mjData* d = env.data();
  const bool first_touch = env.state().kick_touched && !was_touched_;
  was_touched_ = env.state().kick_touched;
  double acceleration = std::numeric_limits<double>::quiet_NaN();
  const auto tracked = std::find(bodies_.begin(), bodies_.end(), env.state().touched_body);
  if (first_touch && tracked != bodies_.end()) {
    // The impulse's direction: the ball's velocity change less what gravity and the env's
    // constant force on the ball (env.ball_force) gave it.
    const double dt = spec.control_dt();
    const config::Vec3& force = spec.env().ball_force();
    const double per_mass = dt / m->body_mass[spec.ball_body()];
    double n[3];
    mju_sub3(n, d->qvel + spec.ball_dof(), ball_velocity_);
    n[0] -= force.x() * per_mass;
    n[1] -= force.y() * per_mass;
    n[2] -= force.z() * per_mass - spec.env().gravity() * dt;
    if (mju_normalize3(n) < 0.05) {  // a graze: straight up
      n[0] = n[1] = 0;
      n[2] = 1;
    }
    const size_t i = tracked - bodies_.begin();
    double change[3];
    mju_sub3(change, velocity_[0].data() + 3 * i, velocity_[1].data() + 3 * i);
    acceleration = mju_dot3(change, n) / dt;
  }
  velocity_[1].swap(velocity_[0]);
  BodyVelocities(env, d->qvel, &velocity_[0]);
  mju_copy3(ball_velocity_, d->qvel + spec.ball_dof());
  return acceleration;
}

}  // namespace juggle::planner
