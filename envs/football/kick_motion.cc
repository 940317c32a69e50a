#include "envs/football/kick_motion.h"

#include <algorithm>
#include <cmath>

#include "envs/humanoid/pose.h"

namespace juggle::football {
namespace {

// A leg's angles at a key of the motion (the right leg's convention: + abduction moves the
// right foot outward, the left foot inward).
struct LegKey {
  double hip = 0, abduction = 0, knee = 0, ankle = 0, ankle_roll = 0;
};

double Smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3 - 2 * u);
}

LegKey Blend(const LegKey& a, const LegKey& b, double u) {
  const double s = Smoothstep(u);
  return {a.hip + s * (b.hip - a.hip), a.abduction + s * (b.abduction - a.abduction),
          a.knee + s * (b.knee - a.knee), a.ankle + s * (b.ankle - a.ankle),
          a.ankle_roll + s * (b.ankle_roll - a.ankle_roll)};
}

// Writes a leg's pitch angles (hip, knee, ankle) into `pose` for the leg of `hip`, `knee` and
// `ankle`, the hip's rotation a pure pitch.
void SetLegPitch(const humanoid::Joints& joints, const humanoid::JointId ids[3], const LegKey& leg,
                 CharacterPose* pose) {
  const double hip[3] = {-leg.abduction, 0, leg.hip};
  humanoid::SetBallJointRotation(joints, ids[0], hip, pose);
  humanoid::SetHinge(joints, ids[1], leg.knee, pose);
  const double ankle[3] = {leg.ankle_roll, 0, leg.ankle};
  humanoid::SetBallJointRotation(joints, ids[2], ankle, pose);
}

// A leg of pitch `hip` and `knee` and of `abduction` with its sole level: the three pitches
// about parallel axes add up to the sole's, and the ankle rolls back what the hip rolls.
LegKey Level(double hip, double knee, double abduction = 0) {
  return {hip, abduction, knee, -(hip + knee), abduction};
}

}  // namespace

double StepHipRoll(double hip_half_width_m, double leg_length_m) {
  if (leg_length_m <= 0) return 0;
  return std::asin(std::min(1.0, hip_half_width_m / leg_length_m));
}

double StepHipPitch(double length_m, double leg_length_m) {
  if (length_m <= 0 || leg_length_m <= 0) return 0;
  return std::asin(std::min(1.0, 0.5 * length_m / leg_length_m));
}

namespace {

// The step's pose at kick-clock `t` inside [times.step, times.plant): the right (standing) leg
// and the left (stepping) one. `pitch`: StepHipPitch; `roll`: the legs' roll that puts the
// pelvis over the right foot (as an abduction of the right leg's convention, both legs alike).
void StepLegs(const config::KickStep& step, const KickTimes& times, double pitch, double roll,
              double leg_length_m, double t, LegKey* right, LegKey* left) {
  if (t < times.step_swing) {  // the pelvis moves over the right foot
    *right = *left = Level(0, 0, roll * StepShiftShare(times, t));
    return;
  }
  const double u = (t - times.step_swing) / (times.plant - times.step_swing);
  const double s = Smoothstep(u);
  *right = Level(-pitch * s, 0, roll);
  // The knee bends by `lift` at mid-swing and the hip flexes by half as much, so the shank
  // swings back by as much as the thigh forward and the foot rises over where it would pass.
  const double lift = step.lift() * std::sin(M_PI * std::clamp(u, 0.0, 1.0));
  // Outward: a left leg's negative abduction (the right leg's convention).
  const double out = std::asin(std::clamp(step.outward_m() / leg_length_m, -1.0, 1.0));
  *left = Level(pitch * s + 0.5 * lift, -lift, roll - out * s);
}

// The left leg as a placement puts it, the knee at `knee`, the sole level in the world.
LegKey Placed(const StepPlacement& p, double knee) {
  return {p.hip_pitch, -p.hip_roll, knee, -(p.pelvis_pitch + p.hip_pitch + knee) - p.toe_down,
          -(p.pelvis_roll + p.hip_roll)};
}

}  // namespace

double StepShiftShare(const KickTimes& times, double t) {
  if (times.step_swing <= times.step || t < times.step) return 0;
  return Smoothstep((t - times.step) / (times.step_swing - times.step));
}

double StepTransferShare(const KickTimes& times, double t) {
  if (times.start <= times.plant || t < times.plant) return 0;
  return Smoothstep((t - times.plant) / (times.start - times.plant));
}

double StepComAhead(const config::KickMotion& motion, const KickTimes& times, double t) {
  if (times.plant <= times.step_swing || t < times.step_swing || t >= times.plant) return 0;
  const double u = (t - times.step_swing) / (times.plant - times.step_swing);
  return 0.5 * motion.step().com_ahead() * motion.step().length_m() * Smoothstep(u);
}

StepPlacement StepPlacementOf(const FootballSpec& spec, const mjData& data, const KickTimes& times,
                              double t) {
  const config::KickStep& step = spec.football().motion().step();
  const mjModel* m = spec.model();
  const double* standing = spec.left_ankle_standing();
  double target[2] = {standing[0] + step.length_m(), standing[1] + step.outward_m()};
  if (t >= times.plant) mju_copy(target, data.xpos + 3 * spec.left_ankle_body(), 2);
  const double* hip = data.xpos + 3 * m->dof_bodyid[spec.joints()[humanoid::kLeftHip].dof_adr];
  const double height = std::max(0.3, hip[2] - standing[2]);
  double tilt[3];  // the pelvis's rotation from upright, in its own frame
  mju_subQuat(tilt, data.qpos + 3, humanoid::kUprightRoot);
  StepPlacement p;
  p.pelvis_pitch = tilt[2];
  p.pelvis_roll = tilt[0];
  p.hip_pitch = std::atan2(target[0] - hip[0], height) - tilt[2];
  p.hip_roll = std::atan2(target[1] - hip[1], height) - tilt[0];
  return p;
}

KickTimes KickTimesOf(const config::KickMotion& m, const KickAdjust& adjust) {
  KickTimes t;
  t.step = t.step_swing = t.plant = t.start = m.start_s() - adjust.timing_s;
  if (m.step().length_m() > 0) {
    t.step_swing = t.step + m.step().shift_s();
    t.plant = t.step_swing + m.step().swing_s();
    t.start = t.plant + m.step().transfer_s();
  }
  t.swing = t.start + m.backswing_s();
  t.recover = t.swing + m.swing_s();
  t.end = t.recover + m.recover_s();
  return t;
}

void KickReferencePose(const FootballSpec& spec, double t, const KickAdjust& adjust,
                       CharacterPose* pose, const StepPlacement* place) {
  *pose = spec.standing_pose();
  const config::KickMotion& m = spec.football().motion();
  const KickTimes times = KickTimesOf(m, adjust);
  if (t <= times.step || t >= times.end) return;
  const humanoid::Joints& joints = spec.joints();
  constexpr humanoid::JointId kRight[3] = {humanoid::kRightHip, humanoid::kRightKnee,
                                           humanoid::kRightAnkle};
  constexpr humanoid::JointId kLeft[3] = {humanoid::kLeftHip, humanoid::kLeftKnee,
                                          humanoid::kLeftAnkle};
  const bool stepped = times.start > times.step;
  const double pitch = stepped ? StepHipPitch(m.step().length_m(), spec.leg_length_m()) : 0;
  // The pelvis over the right foot: both legs lean toward the left (the right leg adducts).
  const double roll =
      stepped ? -StepHipRoll(m.step().shift() * spec.hip_half_width_m(), spec.leg_length_m()) : 0;
  const double out =
      stepped ? std::asin(std::clamp(m.step().outward_m() / spec.leg_length_m(), -1.0, 1.0)) : 0;
  if (t < times.plant) {  // the step
    LegKey right, left;
    StepLegs(m.step(), times, pitch, roll, spec.leg_length_m(), t, &right, &left);
    const double mid = 0.5 * (times.step_swing + times.plant);
    if (place != nullptr && t > mid) {
      left = Blend(left, Placed(*place, left.knee), (t - mid) / (times.plant - mid));
    }
    SetLegPitch(joints, kRight, right, pose);
    SetLegPitch(joints, kLeft, left, pose);
    return;
  }
  // After a transfer the legs' roll is gone: the pelvis between the feet again.
  const double roll_left = roll * (1 - StepTransferShare(times, t));
  const LegKey down = place != nullptr ? Placed(*place, 0) : Level(pitch, 0, roll_left - out);
  if (t < times.start) {  // the weight's transfer onto the planted foot
    SetLegPitch(joints, kRight, Level(-pitch, 0, roll_left), pose);
    SetLegPitch(joints, kLeft, down, pose);
    return;
  }
  // Where the back-swing starts: the standing pose, or where the step left the legs.
  const LegKey rest;
  const LegKey planted = stepped ? Level(-pitch, 0, roll_left) : rest;
  const LegKey back{-m.hip_back(), adjust.abduction, -m.knee_back(), m.ankle_pitch() + adjust.ankle};
  const LegKey forward{m.hip_forward() + adjust.hip, adjust.abduction,
                       -(m.knee_forward() + adjust.knee), m.ankle_pitch() + adjust.ankle};
  LegKey leg;
  if (t < times.swing) {
    const double u = (t - times.start) / (times.swing - times.start);
    leg = Blend(planted, back, u);
    // The pelvis comes over the new standing foot as its hip straightens.
    if (stepped) {
      SetLegPitch(joints, kLeft, m.step().keep_placed() ? down : Blend(down, rest, u), pose);
    }
  } else if (t < times.recover) {
    const double u = (t - times.swing) / (times.recover - times.swing);
    leg = Blend(back, forward, u);
    // The knee's own ease, lagging the hip's by knee_lag of the swing.
    const double lag = m.knee_lag();
    if (lag > 0) leg.knee = Blend(back, forward, (u - lag) / (1 - lag)).knee;
    if (stepped && m.step().keep_placed()) SetLegPitch(joints, kLeft, down, pose);
  } else {
    leg = Blend(forward, rest, (t - times.recover) / (times.end - times.recover));
  }
  // Flexion about z and abduction about x (−x moves the right limb toward +z, outward).
  SetLegPitch(joints, kRight, leg, pose);
}

}  // namespace juggle::football
