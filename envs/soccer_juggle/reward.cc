#include "envs/soccer_juggle/reward.h"

#include <algorithm>
#include <cmath>

#include "envs/ballistic.h"
#include "envs/soccer_juggle/reference_pose.h"

namespace juggle::soccer_juggle {

RewardTerms TrackingReward(const JuggleSpec& spec, const mjData& data,
                           const CharacterPose& reference, const BallReference& ball_ref) {
  const config::RewardConfig& w = spec.env().reward();
  const double* qpos = data.qpos;
  const double* qvel = data.qvel;
  double joint_err = 0;
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec.joint(j);
    const int adr = joint.qpos_adr;
    if (joint.dofs == 3) {
      joint_err += RotationSin2(qpos + adr, reference.data() + adr);
    } else {
      const double d = qpos[adr] - reference[adr];
      joint_err += d * d;
    }
  }
  const double dz = qpos[2] - reference[2];
  const double pos_err = qvel[0] * qvel[0] + qvel[1] * qvel[1] + dz * dz;
  const double ori_err = RotationSin2(qpos + 3, reference.data() + 3);
  const double* ball = qpos + spec.ball_qpos();
  const double bx = ball_ref.x - (ball[0] - qpos[0]);
  const double by = ball_ref.y - (ball[1] - qpos[1]);
  const double bz = ball_ref.z - ball[2];
  const double ball_err = bx * bx + by * by + w.ball_z_weight() * bz * bz;
  RewardTerms terms;
  terms.position = w.w_position() * std::exp(-pos_err);
  terms.orientation = w.w_orientation() * std::exp(-w.orientation_k() * ori_err);
  terms.joint = w.w_joint() * std::exp(-w.joint_k() * joint_err);
  terms.ball = w.w_ball() * std::exp(-ball_err);
  terms.scale = w.scale();
  return terms;
}

float KickReward(const JuggleSpec& spec, const mjData& data, const CursorState& cursor) {
  const config::RewardConfig& w = spec.env().reward();
  const double* ball = data.qpos + spec.ball_qpos();
  const double* ball_vel = data.qvel + spec.ball_dof();
  // The DOWN node the ball is sent to: the next one after the current node.
  int target = cursor.next;
  if (spec.graph().node(cursor.current).stage == config::DOWN) target = cursor.next_next;
  if (spec.graph().node(target).stage != config::DOWN) return 0;  // stalls: no ballistic target
  const config::NodeSpec& node = spec.graph().node(target).spec;
  const double g = spec.env().gravity();
  const double apex = ApexHeight(ball[2], ball_vel[2], g);
  const double t_land =
      SecondsToFall(ball_vel[2], std::max(0.0, ball[2] - node.contact_height()), g);
  const double* root = data.qpos;
  const double dx = ball[0] + ball_vel[0] * t_land - root[0] - node.ball_target().x();
  const double dy = ball[1] + ball_vel[1] * t_land - root[1] - node.ball_target().y();
  const double de = apex - NominalApexHeight(node, g);
  return static_cast<float>(
      w.w_kick() * std::exp(-w.kick_apex_k() * de * de - w.kick_landing_k() * (dx * dx + dy * dy)));
}

}  // namespace juggle::soccer_juggle
