#include "envs/soccer_juggle/start_state.h"

#include "envs/soccer_juggle/reference_pose.h"

namespace juggle::soccer_juggle {
namespace {

// Adds `start`'s uniform noise to the ball's position and velocity and to every actuated
// joint's angle (ball joints: a rotation vector) and speed.
void PerturbStart(const JuggleSpec& spec, const config::StartVariation& start, Rng* rng,
                  mjData* data) {
  double* qpos = data->qpos;
  double* qvel = data->qvel;
  auto noise = [rng](double amplitude) {
    return amplitude > 0 ? rng->Uniform(-amplitude, amplitude) : 0.0;
  };
  double* ball = qpos + spec.ball_qpos();
  double* ball_vel = qvel + spec.ball_dof();
  for (int c = 0; c < 3; ++c) ball[c] += noise(start.ball_position());
  for (int c = 0; c < 3; ++c) ball_vel[c] += noise(start.ball_velocity());
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec.joint(j);
    if (joint.dofs == 3) {
      double rotation[3];
      for (double& r : rotation) r = noise(start.joint_angle());
      mju_quatIntegrate(qpos + joint.qpos_adr, rotation, 1.0);
    } else {
      qpos[joint.qpos_adr] += noise(start.joint_angle());
    }
    for (int d = 0; d < joint.dofs; ++d) qvel[joint.dof_adr + d] += noise(start.joint_speed());
  }
}

}  // namespace

void PlaceAtStart(const JuggleSpec& spec, Rng* rng, CursorState* cursor, CharacterPose* reference,
                  mjData* data) {
  const mjModel* model = spec.model();
  mj_resetData(model, data);
  const config::StartVariation& start = spec.env().start();
  // A random phase of the initial DOWN node: the fall is already under way.
  double fall_s = 0;
  if (start.random_phase_fraction() > 0 &&
      spec.graph().node(cursor->current).stage == config::DOWN &&
      rng->Uniform() < start.random_phase_fraction()) {
    cursor->phase = rng->Uniform(0, start.max_phase());
    fall_s = cursor->phase / cursor->phase_speed * spec.control_dt();
  }
  ComputeCursorPose(spec, *cursor, cursor->phase, reference);
  mju_copy(data->qpos, reference->data(), kCharacterNq);
  const BallReference ball = spec.cursor().DesiredBall(*cursor, cursor->phase);
  double* ball_qpos = data->qpos + spec.ball_qpos();
  ball_qpos[0] = (*reference)[0] + ball.x;
  ball_qpos[1] = (*reference)[1] + ball.y;
  ball_qpos[2] = ball.z;
  ball_qpos[3] = 1;
  ball_qpos[4] = ball_qpos[5] = ball_qpos[6] = 0;
  mju_zero(data->qvel, model->nv);
  data->qvel[spec.ball_dof() + 2] = -spec.env().gravity() * fall_s;
  PerturbStart(spec, start, rng, data);
  mj_forward(model, data);
}

}  // namespace juggle::soccer_juggle
